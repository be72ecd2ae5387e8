#include "sf/examples/factory_data.hpp"

#include <random>
#include <string>

#include <fmt/format.h>

#include "sf/knowledge/vocab.hpp"

namespace sf::examples {

using namespace knowledge;  // NOLINT(google-build-using-namespace): the generator writes RDF throughout

namespace {

class Generator {
 public:
  Generator(Dictionary& d, const FactoryDataOptions& o) : d_(d), o_(o), rng_(o.seed) {
    type_ = d_.iri(vocab::kRdfType);
    label_ = d_.iri(vocab::kRdfsLabel);
  }

  std::vector<Triple> run() {
    for (std::uint32_t line = 1; out_.size() < o_.target_triples; ++line) {
      production_line(line);
    }
    return std::move(out_);
  }

 private:
  // --- terms ---------------------------------------------------------------------------
  TermId sf(std::string_view local) { return d_.iri(std::string(vocab::kSf) + std::string(local)); }
  TermId ind(const std::string& local) { return d_.iri(std::string(kFactoryDataNamespace) + local); }
  TermId dbl(double v) { return d_.literal(fmt::format("{:.1f}", v), vocab::kXsdDouble); }
  TermId integer(long v) { return d_.literal(std::to_string(v), vocab::kXsdInteger); }
  TermId int32(int v) { return d_.literal(std::to_string(v), vocab::kXsdInt); }
  TermId boolean(bool v) { return d_.literal(v ? "true" : "false", vocab::kXsdBoolean); }
  TermId text(const std::string& v) { return d_.literal(v); }
  TermId time(long minutes) {
    // Minutes after 2024-05-01T06:00:00Z.
    const long h = 6 + minutes / 60;
    return d_.literal(fmt::format("2024-05-{:02}T{:02}:{:02}:00Z", 1 + h / 24, h % 24, minutes % 60),
                      vocab::kXsdDateTime);
  }

  void add(TermId s, TermId p, TermId o) { out_.push_back(Triple{s, p, o}); }
  void add(TermId s, std::string_view p, TermId o) { add(s, sf(p), o); }
  void a(TermId s, std::string_view cls) { add(s, type_, sf(cls)); }

  // --- randomness ------------------------------------------------------------------------
  bool chance(double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < p; }
  bool violate() { return chance(o_.violation_rate); }
  long between(long lo, long hi) { return std::uniform_int_distribution<long>(lo, hi)(rng_); }
  double tenths(double lo, double hi) {
    return static_cast<double>(between(static_cast<long>(lo * 10), static_cast<long>(hi * 10))) / 10.0;
  }

  // --- equipment ---------------------------------------------------------------------------
  void machine(TermId m, std::string_view cls, const std::string& manufacturer, const std::string& model,
               std::initializer_list<std::string_view> capabilities) {
    a(m, cls);
    add(m, "manufacturer", text(manufacturer));
    add(m, "model", text(model));
    add(m, "maxTemperature", dbl(70.0));
    add(m, "minTemperature", dbl(5.0));
    double t = tenths(20, 60);
    if (violate()) {
      t = chance(0.8) ? tenths(70.5, 90) : tenths(-5, 4.5);
    }
    add(m, "temperature", dbl(t));
    add(m, "state", text(violate() ? "fault: overcurrent" : (chance(0.7) ? "running" : "idle")));
    for (std::string_view c : capabilities) {
      add(m, "canPerform", sf(c));
    }
    maybe_alarm(m);
  }

  void maybe_alarm(TermId e) {
    if (!chance(0.05)) {
      return;
    }
    const TermId al = ind(fmt::format("alarm{}", ++alarms_));
    a(al, "Alarm");
    add(al, label_,
        text(fmt::format("alarm {} of {}", alarms_, d_.term(e).text.substr(kFactoryDataNamespace.size()))));
    add(al, "acknowledged", boolean(chance(0.5)));
    add(e, "alarm", al);
  }

  // The legacy controller and the Raspberry Pi gateway that speaks OPC UA and DDS for it.
  void legacy(TermId m, const std::string& name, const std::string& plc_maker) {
    const TermId plc = ind(name + ".PLC");
    a(plc, "LegacyPLC");
    add(plc, "manufacturer", text(plc_maker));
    const TermId gw = ind(name + ".Gateway");
    a(gw, "Gateway");
    add(gw, "model", text("Raspberry Pi"));
    add(gw, "gatewayFor", plc);
    add(gw, "endpointUrl",
        d_.literal(fmt::format("opc.tcp://{}.local:4840", name), std::string(vocab::kXsd) + "anyURI"));
    add(m, "controlledBy", plc);
    add(m, "hasComponent", plc);
  }

  void servo_axis(TermId slave, const std::string& prefix, int index) {
    const TermId ax = ind(fmt::format("{}.Axis{}", prefix, index));
    a(ax, "ServoAxis");
    add(ax, "axisIndex", int32(index));
    add(ax, "minPosition", dbl(-170.0));
    add(ax, "maxPosition", dbl(170.0));
    add(ax, "position", dbl(violate() ? tenths(170.5, 200) : tenths(-160, 160)));
    add(ax, "speed", dbl(tenths(0, 90)));
    add(slave, "hasComponent", ax);
  }

  void io(TermId slave, const std::string& prefix, bool input, int channel) {
    const TermId ch = ind(fmt::format("{}.{}{}", prefix, input ? "DI" : "DO", channel));
    a(ch, input ? "DigitalInput" : "DigitalOutput");
    add(ch, "channel", int32(channel));
    add(ch, "digitalValue", boolean(chance(0.5)));
    add(slave, "hasComponent", ch);
  }

  // SCARA Robot 1 with the smart controller and its EtherCAT slave (paper §VII.A).
  TermId smart_robot(TermId line, const std::string& p) {
    const TermId robot = ind(p + ".Robot1");
    machine(robot, "ScaraRobot", "smartfactory", "SCARA Robot 1", {"PickAndPlace", "BoxLoading"});
    const TermId ctrl = ind(p + ".SmartController");
    a(ctrl, "SmartController");
    add(ctrl, "endpointUrl",
        d_.literal(fmt::format("opc.tcp://{}-ipc.local:4840", p), std::string(vocab::kXsd) + "anyURI"));
    add(robot, "hasComponent", ctrl);
    add(robot, "controlledBy", ctrl);
    const TermId slave = ind(p + ".Slave1");
    a(slave, "EtherCATSlave");
    add(slave, "model", text("ET1100 smart controller slave"));
    add(slave, "stationAddress", d_.literal("4097", std::string(vocab::kXsd) + "unsignedShort"));
    add(slave, "inputCount", int32(32));
    add(slave, "outputCount", int32(32));
    add(ctrl, "hasComponent", slave);
    for (int i = 1; i <= 8; ++i) {
      servo_axis(slave, p + ".Slave1", i);
    }
    for (int i = 1; i <= 32; ++i) {
      io(slave, p + ".Slave1", true, i);
      io(slave, p + ".Slave1", false, i);
    }
    add(line, "hasComponent", robot);
    return robot;
  }

  TermId legacy_machine(TermId line, const std::string& p, const std::string& name, std::string_view cls,
                        const std::string& maker, const std::string& model, const std::string& plc_maker,
                        std::initializer_list<std::string_view> capabilities) {
    const TermId m = ind(p + "." + name);
    machine(m, cls, maker, model, capabilities);
    legacy(m, p + "." + name, plc_maker);
    add(line, "hasComponent", m);
    return m;
  }

  void conveyors(TermId line, const std::string& p, TermId from, TermId to) {
    TermId previous = from;
    for (int i = 1; i <= 5; ++i) {
      const TermId c = ind(fmt::format("{}.Conveyor{}", p, i));
      a(c, "Conveyor");
      add(c, "length", dbl(tenths(1.5, 4)));
      add(c, "maxSpeed", dbl(0.8));
      add(c, "speed", dbl(violate() ? tenths(0.9, 1.2) : tenths(0.2, 0.8)));
      add(c, "state", text(violate() ? "fault: belt slip" : "running"));
      add(c, "canPerform", sf("Conveying"));
      add(c, "connectedTo", previous);
      legacy(c, fmt::format("{}.Conveyor{}", p, i), "Siemens");
      add(line, "hasComponent", c);
      maybe_alarm(c);
      previous = c;
    }
    add(previous, "connectedTo", to);
  }

  // --- orders -------------------------------------------------------------------------------
  void order(const std::string& p, std::uint32_t n, TermId robot, TermId other_robot, TermId uploader,
             TermId downloader) {
    ++orders_;
    const TermId o = ind(fmt::format("{}.Order{}", p, n));
    a(o, "Order");
    add(o, "orderCode", text(fmt::format("ORD-{:06}", orders_)));
    const long placed = between(0, 600);
    add(o, "orderedAt", time(placed));
    add(o, "dueAt", time(placed + 120));
    const bool large = chance(0.4);
    const long capacity = large ? 30 : 12;
    add(o, "boxType", sf(large ? "LargeBox" : "SmallBox"));
    const TermId box = ind(fmt::format("{}.Box{}", p, n));
    a(box, "CandyBox");
    add(box, "forOrder", o);
    add(box, "processedBy", robot);
    static constexpr std::string_view kTypes[] = {"Chocolate", "Gummy", "Lollipop", "Toffee"};
    const long lines = between(1, 3);
    long filled = 0;
    for (long k = 0; k < lines; ++k) {
      const TermId line = ind(fmt::format("{}.Order{}.Line{}", p, n, k + 1));
      const std::string_view type = kTypes[(static_cast<std::size_t>(n) + static_cast<std::size_t>(k)) % 4];
      long quantity = between(1, capacity / 3);
      if (violate()) {
        quantity = capacity + between(1, 5);
      }
      a(line, "OrderLine");
      add(line, "forOrder", o);
      add(o, "hasLine", line);
      add(line, "candyType", sf(type));
      add(line, "quantity", integer(quantity));
      const TermId content = ind(fmt::format("{}.Box{}.Content{}", p, n, k + 1));
      a(content, "BoxContent");
      add(box, "hasContent", content);
      add(content, "candyType", sf(type));
      const long counted = violate() ? quantity + (chance(0.5) ? 1 : -1) : quantity;
      add(content, "count", integer(counted));
      filled += counted;
      operation(fmt::format("{}.Order{}.Load{}", p, n, k + 1), o, "PickAndPlace",
                violate() ? uploader : (chance(0.5) ? robot : other_robot));
    }
    add(box, "candyCount", integer(violate() ? capacity + between(1, 3) : std::min(filled, capacity)));
    add(box, "completedAt", time(placed + (violate() ? between(121, 200) : between(10, 119))));
    operation(fmt::format("{}.Order{}.Upload", p, n), o, "BoxLoading", uploader);
    operation(fmt::format("{}.Order{}.Download", p, n), o, "BoxUnloading",
              chance(0.03) ? kNoTerm : downloader);
  }

  void operation(const std::string& name, TermId o, std::string_view capability, TermId machine) {
    const TermId op = ind(name);
    a(op, "Operation");
    add(op, "forOrder", o);
    add(op, "requiresCapability", sf(capability));
    if (machine != kNoTerm) {
      add(op, "assignedTo", machine);
    }
  }

  void production_line(std::uint32_t n) {
    const std::string p = fmt::format("L{}", n);
    const TermId line = ind(p);
    a(line, "ProductionLine");
    add(line, label_, text(fmt::format("packing line {}", n)));
    const TermId robot1 = smart_robot(line, p);
    const TermId robot2 = legacy_machine(line, p, "Robot2", "ArticulatedRobot", "DENSO", "VS-6577G",
                                         "DENSO RC8", {"PickAndPlace", "Palletising"});
    const TermId robot3 = legacy_machine(line, p, "Robot3", "ScaraRobot", "TOSHIBA", "THL300",
                                         "TOSHIBA TS3000", {"PickAndPlace"});
    // Modelling mistakes the OWL rules catch: a robot typed with two disjoint classes, a
    // functional live value with two readings.
    if (violate()) {
      a(robot3, "ArticulatedRobot");
    }
    if (violate()) {
      add(robot3, "temperature", dbl(tenths(20, 60)));
    }
    const TermId uploader = legacy_machine(line, p, "Uploader", "BoxUploader", "Mitsubishi", "box uploader",
                                           "Mitsubishi", {"BoxLoading"});
    const TermId downloader = legacy_machine(line, p, "Downloader", "BoxDownloader", "Mitsubishi",
                                             "box downloader", "Mitsubishi", {"BoxUnloading"});
    conveyors(line, p, uploader, downloader);
    for (std::uint32_t k = 1; k <= o_.orders_per_line; ++k) {
      order(p, k, robot1, robot2, uploader, downloader);
    }
  }

  Dictionary& d_;
  const FactoryDataOptions& o_;
  std::mt19937 rng_;
  std::vector<Triple> out_;
  TermId type_ = kNoTerm;
  TermId label_ = kNoTerm;
  std::uint32_t alarms_ = 0;
  std::uint32_t orders_ = 0;
};

}  // namespace

std::vector<Triple> generate_factory_data(Dictionary& dict, const FactoryDataOptions& options) {
  return Generator(dict, options).run();
}

}  // namespace sf::examples
