// The knowledge loop (paper §VI, Fig. 7): live values from the shop floor become properties of
// the ontology's individuals, the incremental reasoner keeps the closure of the requirement rules
// over them, and every violation it derives is an alarm — raised when the violation appears,
// cleared when it goes — with the rule and the facts that explain it.
//
// What becomes which fact (the OPC UA model names of libs/factory → the ontology's names, the
// line's individuals named by line::iri_name as `plant ontology` writes them):
//   /Objects/Machines/<M>/PackML/Status/StateCurrent  (p:<M> sf:state "<PackML state name>")
//   /Objects/Machines/<M>/Fault (not empty)             (p:<M> sf:state "fault: <text>") instead
//   /Objects/OrderService/LastInspection               the order, its lines, its box and the
//        box's content as counted (sf/line/inspection.hpp), as ontology/prototype-snapshot.ttl
//        shows them: sf:Order, sf:OrderLine (sf:forOrder, sf:candyType, sf:quantity),
//        sf:CandyBox (sf:forOrder, sf:candyCount, sf:hasContent, sf:completedAt),
//        sf:BoxContent (sf:candyType, sf:count; every candy type ordered or found, zero
//        included; a type found but not ordered gets an order line of quantity 0), and sf:dueAt
//        of the order when a due time is configured.
// Any other series is left alone. A value that cannot be read (a malformed inspection) is
// counted and reported in status(), never fatal.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/cloud/live_bus.hpp"
#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"
#include "sf/line/layout.hpp"

namespace sf::cloud {

struct Alarm {
  std::string id;                  // stable for one violation: the entity and the message
  std::string entity;              // the individual's IRI
  std::string rule;                // the rule that derived it
  std::string message;             // the violation's text
  std::vector<std::string> facts;  // the matched triples (N-Triples), the explanation
  bool active = true;              // false: the violation went (cleared)
  historian::Timestamp time{};     // source time of the value that raised or cleared it
};

struct KnowledgeLoopOptions {
  // Turtle: the ontology (classes, properties, catalog individuals as `plant ontology` writes).
  std::string ontology;
  std::string rules;  // Jena rule text
  std::string rules_name = "<rules>";
  // An order is due this long after it was accepted (sf:dueAt; the rule `late`); 0: no due times.
  std::chrono::seconds due_after{0};
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

  [[nodiscard]] std::vector<Alarm> active_alarms() const;
  [[nodiscard]] KnowledgeLoopStatus status() const;

  struct Impl;

 private:
  explicit KnowledgeLoop(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The historian's server name of the alarms' events.
inline constexpr std::string_view kKnowledgeServer = "knowledge";

// An alarm as a historian event (BaseEventType fields; fields = JSON of rule, facts, active).
historian::Event alarm_event(const Alarm& alarm, std::string_view server);

}  // namespace sf::cloud
