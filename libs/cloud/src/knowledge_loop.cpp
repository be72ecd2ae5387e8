// The knowledge loop (knowledge_loop.hpp): live values → facts → incremental closure → alarms.
#include "sf/cloud/knowledge_loop.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "inspection_facts.hpp"
#include "live_facts.hpp"
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

constexpr std::string_view kInspection = "/OrderService/LastInspection";

// "1.5", "80.0": a value in the ontology's unit to a thousandth (the travel limits are written
// to a tenth), as an xsd:double's lexical form the rules' messages show.
std::string decimal(double v) {
  const double rounded = std::round(v * 1000.0) / 1000.0;
  return rounded == std::floor(rounded) ? fmt::format("{:.1f}", rounded) : fmt::format("{}", rounded);
}

// FNV-1a, 64 bits: an alarm id that is the same in every run and every process.
std::uint64_t fnv1a(std::string_view text, std::uint64_t h = 14695981039346656037ULL) {
  for (const char c : text) {
    h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  }
  return h;
}

}  // namespace

struct KnowledgeLoop::Impl {
  mutable std::mutex mutex;
  kb::Dictionary dict;
  std::unique_ptr<kb::Reasoner> reasoner;
  std::chrono::seconds due_after{0};
  Clock* clock = nullptr;
  AlarmSink sink;
  std::map<std::string, Alarm> retained;  // by id: active, or cleared and not acknowledged
  // The current value of a functional live property (a fault state, a position, a temperature)
  // of a subject, replaced by the next.
  std::map<std::pair<kb::TermId, kb::TermId>, kb::TermId> current;
  std::set<kb::TermId> live_properties;  // rdfs:subPropertyOf sf:liveValue: not part of an alarm's id
  std::set<std::string> orders;          // orders whose triples are in
  struct BoxIn {
    historian::Timestamp at;
    std::vector<kb::Triple> triples;  // the box's own, replaced when it is inspected again
  };
  std::map<std::string, BoxIn> boxes;  // by "order box"
  // Per series of a current value: the source time of the value applied last. A value read back
  // from history after a reconnect may be older than one the subscription delivered.
  std::map<std::string, historian::Timestamp> newest;
  KnowledgeLoopStatus st;

  kb::TermId sf(std::string_view local) { return detail::ontology_term(dict, local); }
  kb::TermId p(std::string_view local) { return detail::line_term(dict, local); }

  Status inspection(const LiveUpdate& u);
  bool newer(const LiveUpdate& u);
  void set_current(kb::TermId subject, kb::TermId property, std::optional<kb::TermId> value,
                   historian::Timestamp at);
  Status fault(std::string_view machine, const LiveUpdate& u);
  void quantity(const detail::LiveQuantity& q, const LiveUpdate& u);
  void apply(const Result<kb::UpdateResult>& result, historian::Timestamp at);
  Alarm alarm_of(const kb::Violation& v) const;
  void deliver(const Alarm& a) const {
    if (sink) {
      sink(a);
    }
  }
  void raise_and_clear(historian::Timestamp at);
  void find_live_properties();
};

// A box inspected again (taken off the line, refilled, inspected once more) replaces its own
// triples; the order's lines stay, other boxes of the order may need them.
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
  const std::string key = fmt::format("{} {}", r->order, r->box);
  const auto before = boxes.find(key);
  if (before != boxes.end() && at <= before->second.at) {
    return {};  // delivered again (read back from history), or older than the box's last inspection
  }
  kb::Changes changes;
  detail::InspectionFacts facts(dict, due_after);
  if (orders.insert(r->order).second) {
    facts.order(*r, at, changes.add);
  }
  std::vector<kb::Triple> own;
  facts.box(*r, at, own, changes.add);
  if (before != boxes.end()) {
    for (const kb::Triple& t : before->second.triples) {
      if (std::find(own.begin(), own.end(), t) == own.end()) {
        changes.remove.push_back(t);
      }
    }
  }
  for (const kb::Triple& t : own) {
    if (before == boxes.end() || std::find(before->second.triples.begin(), before->second.triples.end(), t) ==
                                     before->second.triples.end()) {
      changes.add.push_back(t);
    }
  }
  boxes[key] = BoxIn{at, std::move(own)};
  ++st.inspections;
  apply(reasoner->update(changes), at);
  return {};
}

// Whether the update is newer than the value of its series applied last (and from now on the
// one applied).
bool KnowledgeLoop::Impl::newer(const LiveUpdate& u) {
  const std::string series = u.series->server + " " + u.series->node_id;
  if (auto it = newest.find(series); it != newest.end() && u.sample.source_time <= it->second) {
    return false;
  }
  newest[series] = u.sample.source_time;
  return true;
}

// (subject property value) replaces the property's value of the subject; nullopt removes it.
void KnowledgeLoop::Impl::set_current(kb::TermId subject, kb::TermId property,
                                      std::optional<kb::TermId> value, historian::Timestamp at) {
  const auto key = std::make_pair(subject, property);
  kb::Changes changes;
  if (auto it = current.find(key); it != current.end()) {
    if (value && dict.value_id(*value) == dict.value_id(it->second)) {
      return;  // the same value again
    }
    changes.remove.push_back({subject, property, it->second});
    current.erase(it);
  }
  if (value) {
    changes.add.push_back({subject, property, *value});
    current[key] = *value;
  }
  apply(reasoner->update(changes), at);
}

Status KnowledgeLoop::Impl::fault(std::string_view machine, const LiveUpdate& u) {
  const auto* text = std::get_if<std::string>(&u.sample.value);
  if (text == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("{}: a fault is a text", u.series->browse_path));
  }
  if (!newer(u)) {
    return {};
  }
  std::optional<kb::TermId> state;
  if (!text->empty()) {
    state = dict.literal("fault: " + *text);
  }
  set_current(p(machine), sf("state"), state, u.sample.source_time);
  return {};
}

void KnowledgeLoop::Impl::quantity(const detail::LiveQuantity& q, const LiveUpdate& u) {
  if (!newer(u)) {
    return;
  }
  set_current(p(q.individual), sf(q.property), dict.literal(decimal(q.value), vocab::kXsdDouble),
              u.sample.source_time);
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

// The id names the rule, the entity and the explanation's static facts: a live value that
// changes while the violation lasts (a temperature still above its maximum) keeps the alarm.
Alarm KnowledgeLoop::Impl::alarm_of(const kb::Violation& v) const {
  Alarm a;
  a.entity = std::string(dict.term(v.triple.s).text);
  a.message = std::string(dict.term(v.triple.o).text);
  a.rule = v.because.rule != nullptr ? v.because.rule->label() : std::string();
  std::uint64_t h = fnv1a(a.rule, fnv1a(a.entity));
  for (const kb::TripleId premise : v.because.premises) {
    const kb::Triple t = reasoner->store().at(premise);
    a.facts.push_back(kb::format_triple(dict, t));
    if (!live_properties.contains(t.p)) {
      h = fnv1a(a.facts.back(), h);
    }
  }
  a.id = fmt::format("{}-{:016x}", a.rule, h);
  return a;
}

void KnowledgeLoop::Impl::raise_and_clear(historian::Timestamp at) {
  std::map<std::string, Alarm> now;
  for (const auto& v : reasoner->violations()) {
    Alarm a = alarm_of(v);
    now.emplace(a.id, std::move(a));
  }
  for (auto it = retained.begin(); it != retained.end();) {
    Alarm& a = it->second;
    const auto still = now.find(it->first);
    if (!a.active || still != now.end()) {
      if (a.active) {  // the live values moved: the message and the facts follow
        a.message = still->second.message;
        a.facts = still->second.facts;
      }
      ++it;
      continue;
    }
    a.active = false;
    a.change = AlarmChange::cleared;
    a.time = at;
    deliver(a);
    it = a.acked ? retained.erase(it) : std::next(it);
  }
  for (auto& [id, a] : now) {
    if (auto it = retained.find(id); it != retained.end() && it->second.active) {
      continue;
    }
    a.time = at;  // new, or raised again while its clearing waits for an acknowledgement
    deliver(retained.insert_or_assign(id, std::move(a)).first->second);
  }
  st.active_alarms = static_cast<std::size_t>(
      std::count_if(retained.begin(), retained.end(), [](const auto& e) { return e.second.active; }));
  st.triples = reasoner->store().size();
}

// The properties whose values change at run time (OPC UA variables): rdfs:subPropertyOf
// sf:liveValue in the ontology.
void KnowledgeLoop::Impl::find_live_properties() {
  const kb::TermId sub = dict.iri(vocab::kRdfsSubPropertyOf);
  const kb::TermId live = dict.value_id(sf("liveValue"));
  const auto& store = reasoner->store();
  store.match(kb::ValuePattern{kb::kNoTerm, sub, live}, store.next_id(),
              [&](kb::TripleId id) { live_properties.insert(store.at(id).s); });
}

Result<std::unique_ptr<KnowledgeLoop>> KnowledgeLoop::create(const line::Layout& layout,
                                                             const KnowledgeLoopOptions& options,
                                                             AlarmSink sink) {
  auto impl = std::make_unique<Impl>();
  impl->due_after = options.due_after;
  impl->clock = options.clock;
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
  impl->find_live_properties();
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
  } else if (auto machine = detail::machine_of(path, "Fault")) {
    done = impl_->fault(*machine, update);
  } else if (auto q = detail::live_quantity(path, update.series->unit, update.sample.value)) {
    if (*q) {
      impl_->quantity(**q, update);
    } else {
      done = q->error();
    }
  } else {
    return;
  }
  if (!done) {
    ++impl_->st.rejected;
    impl_->st.last_error = fmt::format("{}: {}", path, done.error().describe());
  }
}

Status KnowledgeLoop::acknowledge(std::string_view id, std::string_view user, std::string_view comment) {
  std::lock_guard lock(impl_->mutex);
  const auto it = impl_->retained.find(std::string(id));
  if (it == impl_->retained.end()) {
    return make_error(Errc::not_found, fmt::format("no alarm '{}' to acknowledge", id));
  }
  Alarm& a = it->second;
  if (a.acked) {
    return make_error(Errc::state, fmt::format("alarm '{}' is acknowledged already (by {})", id, a.acked_by));
  }
  a.acked = true;
  a.acked_by = std::string(user);
  a.ack_comment = std::string(comment);
  a.change = AlarmChange::acknowledged;
  a.time = std::chrono::time_point_cast<historian::Micros>(impl_->clock->utc_now());
  impl_->deliver(a);
  if (!a.active) {
    impl_->retained.erase(it);  // cleared and acknowledged: the condition is no longer retained
  }
  return {};
}

std::vector<Alarm> KnowledgeLoop::active_alarms() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<Alarm> out;
  for (const auto& [id, a] : impl_->retained) {
    if (a.active) {
      out.push_back(a);
    }
  }
  return out;
}

std::vector<Alarm> KnowledgeLoop::retained_alarms() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<Alarm> out;
  for (const auto& [id, a] : impl_->retained) {
    out.push_back(a);
  }
  return out;
}

KnowledgeLoopStatus KnowledgeLoop::status() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->st;
}

std::string_view to_string(AlarmChange change) {
  switch (change) {
    case AlarmChange::raised:
      return "raised";
    case AlarmChange::cleared:
      return "cleared";
    case AlarmChange::acknowledged:
      return "acknowledged";
  }
  return "?";
}

historian::Event alarm_event(const Alarm& alarm, std::string_view server) {
  historian::Event e;
  e.server = std::string(server);
  // One id per raising, clearing or acknowledgement (Part 5 §6.4.2: EventId unique per event).
  const std::string id =
      fmt::format("{} {} {}", to_string(alarm.change), historian::to_micros(alarm.time), alarm.id);
  e.event_id.assign(id.begin(), id.end());
  e.time = alarm.time;
  e.receive_time = alarm.time;
  e.event_type = "sf:Violation";
  e.source_node = alarm.entity;
  e.source_name = alarm.entity.substr(alarm.entity.find_last_of("/#") + 1);
  e.severity = alarm_severity(alarm);
  e.message = alarm.change == AlarmChange::raised
                  ? alarm.message
                  : fmt::format("{}: {}", to_string(alarm.change), alarm.message);
  e.fields = nlohmann::json{{"id", alarm.id},
                            {"change", to_string(alarm.change)},
                            {"rule", alarm.rule},
                            {"active", alarm.active},
                            {"acked", alarm.acked},
                            {"acked_by", alarm.acked_by},
                            {"ack_comment", alarm.ack_comment},
                            {"facts", alarm.facts}}
                 .dump();
  return e;
}

std::uint16_t alarm_severity(const Alarm& alarm) {
  return alarm.active ? 700 : 100;
}

}  // namespace sf::cloud
