// The knowledge loop (knowledge_loop.hpp): live values → facts → incremental closure → alarms.
#include "sf/cloud/knowledge_loop.hpp"

#include <map>
#include <mutex>
#include <optional>
#include <set>

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/reasoner.hpp"
#include "sf/knowledge/rules.hpp"
#include "sf/knowledge/vocab.hpp"
#include "sf/line/inspection.hpp"
#include "sf/line/ontology.hpp"

namespace sf::cloud {

namespace kb = sf::knowledge;
namespace vocab = sf::knowledge::vocab;

namespace {

constexpr std::string_view kMachines = "/Objects/Machines/";
constexpr std::string_view kFault = "/Fault";
constexpr std::string_view kInspection = "/OrderService/LastInspection";

// An order id as part of an IRI: letters, digits, '-', '.' and '_' stay, anything else is
// percent-encoded (RFC 3987 iunreserved), so every id gives its own valid IRI.
std::string iri_part(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) != 0 || c == '-' || c == '.' || c == '_') {
      out += c;
    } else {
      out += fmt::format("%{:02X}", u);
    }
  }
  return out;
}

std::string xsd_date_time(historian::Timestamp t) {
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}Z", std::chrono::floor<std::chrono::milliseconds>(t));
}

// The machine of "/Objects/Machines/<M>/Fault", or nothing.
std::optional<std::string_view> fault_machine(std::string_view path) {
  const auto at = path.find(kMachines);
  if (at == std::string_view::npos || !path.ends_with(kFault)) {
    return std::nullopt;
  }
  auto machine = path.substr(at + kMachines.size());
  machine.remove_suffix(kFault.size());
  if (machine.empty() || machine.find('/') != std::string_view::npos) {
    return std::nullopt;
  }
  return machine;
}

}  // namespace

struct KnowledgeLoop::Impl {
  mutable std::mutex mutex;
  kb::Dictionary dict;
  std::unique_ptr<kb::Reasoner> reasoner;
  std::chrono::seconds due_after{0};
  AlarmSink sink;
  std::map<std::string, Alarm> active;            // by id
  std::map<std::string, kb::TermId> fault_state;  // machine IRI → its sf:state literal now
  std::set<std::string> orders;                   // orders whose triples are in
  std::set<std::string> boxes;                    // boxes whose triples are in
  // Per series of a current value (faults): the source time of the value applied last. A value
  // read back from history after a reconnect may be older than one the subscription delivered.
  std::map<std::string, historian::Timestamp> newest;
  KnowledgeLoopStatus st;

  kb::TermId sf(std::string_view local) { return dict.iri(fmt::format("{}{}", vocab::kSf, local)); }
  kb::TermId p(std::string_view local) { return dict.iri(fmt::format("{}{}", line::kLineNamespace, local)); }
  kb::TermId integer(int n) { return dict.literal(std::to_string(n), vocab::kXsdInteger); }
  kb::TermId type() { return dict.iri(vocab::kRdfType); }

  void order_facts(const line::InspectionRecord& r, historian::Timestamp at, std::vector<kb::Triple>& add);
  void line_facts(const std::string& order, const std::string& candy, int quantity,
                  std::vector<kb::Triple>& add);
  void box_facts(const line::InspectionRecord& r, historian::Timestamp at, std::vector<kb::Triple>& add);
  Status inspection(const LiveUpdate& u);
  Status fault(std::string_view machine, const LiveUpdate& u);
  void apply(const Result<kb::UpdateResult>& result, historian::Timestamp at);
  Alarm alarm_of(const kb::Violation& v) const;
  void raise_and_clear(historian::Timestamp at);
};

void KnowledgeLoop::Impl::order_facts(const line::InspectionRecord& r, historian::Timestamp at,
                                      std::vector<kb::Triple>& add) {
  const kb::TermId o = p("Order_" + iri_part(r.order));
  add.push_back({o, type(), sf("Order")});
  add.push_back({o, sf("orderCode"), dict.literal(r.order)});
  add.push_back({o, sf("boxType"), sf(line::iri_name(r.box_type))});
  for (const auto& [candy, n] : r.ordered) {
    line_facts(r.order, candy, n, add);
  }
  if (due_after.count() > 0) {
    // Accepted lead_s before this inspection, due due_after after that.
    const auto accepted =
        at - std::chrono::duration_cast<historian::Micros>(std::chrono::duration<double>(r.lead_s));
    add.push_back({o, sf("dueAt"), dict.literal(xsd_date_time(accepted + due_after), vocab::kXsdDateTime)});
  }
}

void KnowledgeLoop::Impl::line_facts(const std::string& order, const std::string& candy, int quantity,
                                     std::vector<kb::Triple>& add) {
  const kb::TermId l = p(fmt::format("Order_{}_{}", iri_part(order), line::iri_name(candy)));
  add.push_back({l, type(), sf("OrderLine")});
  add.push_back({l, sf("forOrder"), p("Order_" + iri_part(order))});
  add.push_back({l, sf("candyType"), sf(line::iri_name(candy))});
  add.push_back({l, sf("quantity"), integer(quantity)});
}

void KnowledgeLoop::Impl::box_facts(const line::InspectionRecord& r, historian::Timestamp at,
                                    std::vector<kb::Triple>& add) {
  const std::string name = fmt::format("Box_{}_{}", iri_part(r.order), r.box);
  const kb::TermId box = p(name);
  add.push_back({box, type(), sf("CandyBox")});
  add.push_back({box, sf("forOrder"), p("Order_" + iri_part(r.order))});
  add.push_back({box, sf("completedAt"), dict.literal(xsd_date_time(at), vocab::kXsdDateTime)});
  int total = 0;
  // Every candy type ordered or found: a type the box lacks altogether is a count of 0.
  std::map<std::string, int> content = r.counted;
  for (const auto& [candy, n] : r.ordered) {
    content.emplace(candy, 0);
  }
  // A type the order does not name is one it asks none of: its line says 0, so contentMismatch
  // reports it ("chocolate: ordered 0, the box holds 2") without a rule of negation, whose
  // result would hang on the order in which a forward engine meets the facts.
  for (const auto& [candy, n] : r.counted) {
    if (!r.ordered.contains(candy)) {
      line_facts(r.order, candy, 0, add);
    }
  }
  for (const auto& [candy, n] : content) {
    const kb::TermId c = p(fmt::format("{}_{}", name, line::iri_name(candy)));
    add.push_back({box, sf("hasContent"), c});
    add.push_back({c, type(), sf("BoxContent")});
    add.push_back({c, sf("candyType"), sf(line::iri_name(candy))});
    add.push_back({c, sf("count"), integer(n)});
    total += n;
  }
  add.push_back({box, sf("candyCount"), integer(total)});
}

Status KnowledgeLoop::Impl::inspection(const LiveUpdate& u) {
  const auto* text = std::get_if<std::string>(&u.sample.value);
  if (text == nullptr || text->empty()) {
    return {};  // no inspection yet
  }
  auto r = line::parse_inspection(*text);
  if (!r) {
    return r.error();
  }
  const historian::Timestamp at = u.sample.source_time;
  if (!boxes.insert(fmt::format("{} {}", r->order, r->box)).second) {
    return {};  // delivered again (read back from history): in already
  }
  kb::Changes changes;
  if (orders.insert(r->order).second) {
    order_facts(*r, at, changes.add);
  }
  box_facts(*r, at, changes.add);
  ++st.inspections;
  apply(reasoner->update(changes), at);
  return {};
}

Status KnowledgeLoop::Impl::fault(std::string_view machine, const LiveUpdate& u) {
  const auto* text = std::get_if<std::string>(&u.sample.value);
  if (text == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("{}: a fault is a text", u.series->browse_path));
  }
  const std::string series = u.series->server + " " + u.series->node_id;
  if (auto it = newest.find(series); it != newest.end() && u.sample.source_time <= it->second) {
    return {};  // not newer than the value applied
  }
  newest[series] = u.sample.source_time;
  const kb::TermId m = p(machine);
  const std::string key(machine);
  kb::Changes changes;
  if (auto it = fault_state.find(key); it != fault_state.end()) {
    changes.remove.push_back({m, sf("state"), it->second});
    fault_state.erase(it);
  }
  if (!text->empty()) {
    const kb::TermId state = dict.literal("fault: " + *text);
    changes.add.push_back({m, sf("state"), state});
    fault_state[key] = state;
  }
  apply(reasoner->update(changes), u.sample.source_time);
  return {};
}

void KnowledgeLoop::Impl::apply(const Result<kb::UpdateResult>& result, historian::Timestamp at) {
  ++st.values;
  if (!result) {
    ++st.rejected;
    st.last_error = result.error().describe();
    return;
  }
  raise_and_clear(at);
}

Alarm KnowledgeLoop::Impl::alarm_of(const kb::Violation& v) const {
  Alarm a;
  a.entity = std::string(dict.term(v.triple.s).text);
  a.message = std::string(dict.term(v.triple.o).text);
  a.id = a.entity + " " + a.message;
  a.rule = v.because.rule != nullptr ? v.because.rule->label() : std::string();
  for (const kb::TripleId premise : v.because.premises) {
    a.facts.push_back(kb::format_triple(dict, reasoner->store().at(premise)));
  }
  return a;
}

void KnowledgeLoop::Impl::raise_and_clear(historian::Timestamp at) {
  std::map<std::string, Alarm> now;
  for (const auto& v : reasoner->violations()) {
    Alarm a = alarm_of(v);
    now.emplace(a.id, std::move(a));
  }
  for (auto it = active.begin(); it != active.end();) {
    if (now.contains(it->first)) {
      ++it;
      continue;
    }
    Alarm cleared = std::move(it->second);
    cleared.active = false;
    cleared.time = at;
    it = active.erase(it);
    if (sink) {
      sink(cleared);
    }
  }
  for (auto& [id, a] : now) {
    if (active.contains(id)) {
      continue;
    }
    a.time = at;
    active.emplace(id, a);
    if (sink) {
      sink(a);
    }
  }
  st.active_alarms = active.size();
  st.triples = reasoner->store().size();
}

Result<std::unique_ptr<KnowledgeLoop>> KnowledgeLoop::create(const line::Layout& layout,
                                                             const KnowledgeLoopOptions& options,
                                                             AlarmSink sink) {
  auto impl = std::make_unique<Impl>();
  impl->due_after = options.due_after;
  impl->sink = std::move(sink);
  auto ontology = kb::read_rdf_string(impl->dict, options.ontology, kb::Syntax::turtle, "<ontology>");
  if (!ontology) {
    return ontology.error();
  }
  const std::string individuals = line::line_turtle(layout, "the cloud's layout");
  auto line_doc = kb::read_rdf_string(impl->dict, individuals, kb::Syntax::turtle, "<line>");
  if (!line_doc) {
    return line_doc.error();
  }
  auto rules = kb::parse_rules(options.rules, options.rules_name, impl->dict);
  if (!rules) {
    return rules.error();
  }
  kb::ReasonerOptions ro;
  ro.print = [](const std::string&) {};  // the alarms say it
  impl->reasoner = std::make_unique<kb::Reasoner>(impl->dict, std::move(*rules), ro);
  impl->reasoner->add_data(ontology->triples);
  impl->reasoner->add_data(line_doc->triples);
  if (auto run = impl->reasoner->run(); !run) {
    return run.error();
  }
  impl->raise_and_clear(historian::Timestamp{});
  return std::unique_ptr<KnowledgeLoop>(new KnowledgeLoop(std::move(impl)));
}

KnowledgeLoop::KnowledgeLoop(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
KnowledgeLoop::~KnowledgeLoop() = default;

void KnowledgeLoop::on_value(const LiveUpdate& update) {
  if (update.series == nullptr) {
    return;
  }
  const std::string_view path = update.series->browse_path;
  std::lock_guard lock(impl_->mutex);
  Status done;
  if (path.ends_with(kInspection)) {
    done = impl_->inspection(update);
  } else if (auto machine = fault_machine(path)) {
    done = impl_->fault(*machine, update);
  } else {
    return;
  }
  if (!done) {
    ++impl_->st.rejected;
    impl_->st.last_error = fmt::format("{}: {}", path, done.error().describe());
  }
}

std::vector<Alarm> KnowledgeLoop::active_alarms() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<Alarm> out;
  for (const auto& [id, a] : impl_->active) {
    out.push_back(a);
  }
  return out;
}

KnowledgeLoopStatus KnowledgeLoop::status() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->st;
}

historian::Event alarm_event(const Alarm& alarm, std::string_view server) {
  historian::Event e;
  e.server = std::string(server);
  // One id per raising or clearing (Part 5 §6.4.2: EventId unique per event).
  const std::string id = fmt::format("{} {} {}", alarm.active ? "raised" : "cleared",
                                     historian::to_micros(alarm.time), alarm.id);
  e.event_id.assign(id.begin(), id.end());
  e.time = alarm.time;
  e.receive_time = alarm.time;
  e.event_type = "sf:Violation";
  e.source_node = alarm.entity;
  e.source_name = alarm.entity.substr(alarm.entity.find_last_of("/#") + 1);
  e.severity = alarm.active ? 700 : 100;
  e.message = (alarm.active ? "" : "cleared: ") + alarm.message;
  e.fields = nlohmann::json{{"rule", alarm.rule}, {"active", alarm.active}, {"facts", alarm.facts}}.dump();
  return e;
}

}  // namespace sf::cloud
