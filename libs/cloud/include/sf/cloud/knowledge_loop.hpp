// The knowledge loop (paper §VI, Fig. 7): live values from the shop floor become properties of
// the ontology's individuals, the incremental reasoner keeps the closure of the requirement rules
// over them, and every violation it derives is an alarm — raised when the violation appears,
// cleared when it goes, acknowledged by an operator — with the rule and the facts that explain it.
//
// What becomes which fact (the OPC UA model names of libs/factory → the ontology's names, the
// line's individuals named by line::iri_name as `plant ontology` writes them):
//   /Objects/Machines/<M>/Fault (not empty)             (p:<M> sf:state "fault: <text>"), gone when
//        the text is empty again (the PackML state itself is not a fact: no rule asks for it)
//   /Objects/Machines/<M>/Tags/axis<N>.position         (p:<M>Axis<N> sf:position v), v in degrees
//        from a rotation unit (the smart robot publishes radians) or in millimetres from a length
//        unit (metres for the z axis), as sf:minPosition/sf:maxPosition of the axis are written
//   /Objects/Machines/<M>/Tags/[<x>.]temperature       (p:<M> sf:temperature v), v in °C
//        (a legacy robot controller's "robot.temperature")
//   /Objects/OrderService/LastInspection               the order, its lines, its box and the
//        box's content as counted (sf/line/inspection.hpp), as ontology/prototype-snapshot.ttl
//        shows them: sf:Order, sf:OrderLine (sf:forOrder, sf:candyType, sf:quantity),
//        sf:CandyBox (sf:forOrder, sf:candyCount, sf:hasContent, sf:completedAt),
//        sf:BoxContent (sf:candyType, sf:count; every candy type ordered or found, zero
//        included; a type found but not ordered gets an order line of quantity 0), and sf:dueAt
//        of the order when a due time is configured. A box inspected again replaces its content.
// The unit of a quantity is the variable's EngineeringUnits (OPC 10000-8 §5.6.3) as the gateway
// read it (SeriesInfo::unit, its display name): rad, °, m, mm, °C, K are converted; a quantity
// without a unit, or in another, is rejected rather than guessed. Any other series is left
// alone. A value that cannot be read (a malformed inspection) is counted and reported in
// status(), never fatal.
//
// An alarm keeps its id while its violation lasts: the rule, the entity and the static facts
// of its explanation name it, not the live values, so a temperature that moves while above its
// maximum stays one alarm (its message follows the value). Like a condition of OPC 10000-9
// §4.3, an alarm is retained while it is active or not yet acknowledged.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/cloud/live_bus.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"
#include "sf/line/layout.hpp"

namespace sf::cloud {

// What one delivery of an alarm reports (OPC 10000-9 §5.8: ActiveState, AckedState changes).
enum class AlarmChange : std::uint8_t { raised, cleared, acknowledged };
std::string_view to_string(AlarmChange change);

struct Alarm {
  std::string id;                  // "<rule>-<16 hex digits>", stable for one violation
  std::string entity;              // the individual's IRI
  std::string rule;                // the rule that derived it
  std::string message;             // the violation's text
  std::vector<std::string> facts;  // the matched triples (N-Triples), the explanation
  bool active = true;              // false: the violation went (cleared)
  bool acked = false;              // an operator acknowledged it
  std::string acked_by;
  std::string ack_comment;
  AlarmChange change = AlarmChange::raised;
  // Source time of the value that raised or cleared it; the clock's time of an acknowledgement.
  historian::Timestamp time{};
};

struct KnowledgeLoopOptions {
  // Turtle: the ontology (classes, properties, catalog individuals as `plant ontology` writes).
  std::string ontology;
  std::string rules;  // Jena rule text
  std::string rules_name = "<rules>";
  // An order is due this long after it was accepted (sf:dueAt; the rule `late`); 0: no due times.
  std::chrono::seconds due_after{0};
  Clock* clock = &SteadyClock::instance();  // the time of acknowledgements
};

struct KnowledgeLoopStatus {
  std::uint64_t values = 0;       // live values that became facts
  std::uint64_t inspections = 0;  // boxes added
  std::uint64_t rejected = 0;     // values that could not be read
  std::string last_error;
  std::size_t active_alarms = 0;
  std::size_t triples = 0;
};

class KnowledgeLoop {
 public:
  using AlarmSink = std::function<void(const Alarm&)>;

  // Reads the ontology, the line's individuals (line::line_turtle of `layout`) and the rules
  // and computes the first closure; errors name the file and place. Violations of the static
  // data are raised at once (on `sink`).
  static Result<std::unique_ptr<KnowledgeLoop>> create(const line::Layout& layout,
                                                       const KnowledgeLoopOptions& options, AlarmSink sink);
  ~KnowledgeLoop();
  KnowledgeLoop(const KnowledgeLoop&) = delete;
  KnowledgeLoop& operator=(const KnowledgeLoop&) = delete;

  // One live value (a LiveBus callback; thread-safe). Alarms it raises or clears go to the sink
  // before it returns.
  void on_value(const LiveUpdate& update);

  // An operator acknowledges the alarm `id` (active, or cleared and not yet acknowledged);
  // delivered to the sink like a raise. Errors: not_found (no such alarm retained), state
  // (acknowledged already).
  Status acknowledge(std::string_view id, std::string_view user, std::string_view comment);

  [[nodiscard]] std::vector<Alarm> active_alarms() const;
  // The alarms retained: active ones and cleared ones not yet acknowledged.
  [[nodiscard]] std::vector<Alarm> retained_alarms() const;
  [[nodiscard]] KnowledgeLoopStatus status() const;

  struct Impl;

 private:
  explicit KnowledgeLoop(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The historian's server name of the alarms' events.
inline constexpr std::string_view kKnowledgeServer = "knowledge";

// An alarm as a historian event (BaseEventType fields; fields = JSON of id, change, rule,
// facts, active, acked, acked_by, ack_comment).
historian::Event alarm_event(const Alarm& alarm, std::string_view server);
// OPC 10000-5 §6.4.2 Severity (1..1000): 700 while active, 100 once cleared.
std::uint16_t alarm_severity(const Alarm& alarm);

}  // namespace sf::cloud
