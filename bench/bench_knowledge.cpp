// Reasoning over generated candy-factory data (libs/knowledge) next to Apache Jena's forward
// RETE engine (GenericRuleReasoner, FORWARD_RETE) in the same run: the same ontology, data and
// rule files (rules/rdfs.rules, owl2rl.rules, candy-factory.rules), each engine in its own
// process so that its peak resident memory (getrusage ru_maxrss) is its own (this program runs
// again for ours, with a --child-* role). Then the latency of
// one live-value change (a machine's temperature) maintained incrementally, in both.
//
//   bench_knowledge [--sizes 100000,1000000] [--updates 200] [--no-jena] [--jena-xmx 16g]
//
// --jena-xmx sets the JVM's maximum heap (default: three quarters of the machine's memory, at
// most 14g; the JVM's own default of a quarter is too small for Jena's RETE network at a
// million triples).
//
// Times: reasoning only (closure from loaded data); "load" is parsing the N-Triples file.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/bench/percentile.hpp"
#include "sf/core/process.hpp"
#include "sf/examples/factory_data.hpp"
#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/reasoner.hpp"
#include "sf/knowledge/vocab.hpp"

namespace {

namespace kb = sf::knowledge;
using Clock = std::chrono::steady_clock;

const std::string kSource = SF_SOURCE_DIR;
const std::vector<std::string> kRules = {kSource + "/rules/rdfs.rules", kSource + "/rules/owl2rl.rules",
                                         kSource + "/rules/candy-factory.rules"};
const std::string kOntology = kSource + "/ontology/candy-factory.ttl";
const std::string kCatalog = kSource + "/ontology/prototype-line.ttl";  // the line's candy and box types

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Measured {
  nlohmann::json result;  // what the child reported
  double peak_mb = 0;     // its peak resident set
  bool ok = false;
};

// The JSON object at the end of `text` that starts with `{"key"` (the last line when `key` is
// empty), or null.
nlohmann::json last_json(std::string text, std::string_view key) {
  while (!text.empty() && text.back() == '\n') {
    text.pop_back();
  }
  const auto line = text.rfind('\n');
  const auto start =
      key.empty() ? (line == std::string::npos ? 0 : line + 1) : text.rfind(fmt::format("{{\"{}\"", key));
  if (start == std::string::npos) {
    return nullptr;
  }
  auto j = nlohmann::json::parse(text.substr(start), nullptr, false);
  return j.is_discarded() ? nlohmann::json(nullptr) : j;
}

// Runs `argv` as a process of its own (so that its peak RSS is its own) and reads its JSON result
// (see last_json) from stdout, or, for the Java peer, from stderr.
Measured measure(std::vector<std::string> argv, std::string_view key, sf::Stream json_on) {
  sf::ProcessOptions o;
  o.argv = std::move(argv);
  o.out = json_on == sf::Stream::out ? sf::Stdio::pipe() : sf::Stdio::null();
  o.err = json_on == sf::Stream::err ? sf::Stdio::pipe() : sf::Stdio::inherit();
  auto done = sf::Process::run(std::move(o), std::chrono::hours{24});
  Measured m;
  if (!done) {
    std::cerr << done.error().describe() << "\n";
    return m;
  }
  const std::string& text = json_on == sf::Stream::out ? done->out : done->err;
  m.peak_mb = static_cast<double>(done->status.max_rss_kib) / 1024.0;
  m.result = last_json(text, key);
  m.ok = done->status.success() && !m.result.is_null();
  if (!m.ok) {
    std::cerr << text.substr(text.size() > 2000 ? text.size() - 2000 : 0) << "\n";
  }
  return m;
}

// This program again, running one of the child roles of main().
std::vector<std::string> self(std::initializer_list<std::string> args) {
  std::vector<std::string> argv = {"/proc/self/exe"};
  argv.insert(argv.end(), args);
  return argv;
}

nlohmann::json ours(const std::string& data, int updates) {
  kb::Dictionary dict;
  const auto t0 = Clock::now();
  std::vector<kb::Triple> triples;
  for (const std::string& f : {kOntology, kCatalog, data}) {
    auto doc = kb::read_rdf_file(dict, f);
    if (!doc) {
      std::cerr << doc.error().message << "\n";
      _exit(1);
    }
    triples.insert(triples.end(), doc->triples.begin(), doc->triples.end());
  }
  kb::RuleSet rules;
  for (const std::string& f : kRules) {
    auto set = kb::read_rules_file(f, dict);
    std::move(set->rules.begin(), set->rules.end(), std::back_inserter(rules.rules));
  }
  const double load_ms = ms_since(t0);
  kb::Reasoner r(dict, std::move(rules), kb::ReasonerOptions{50'000'000, [](const std::string&) {}});
  r.add_data(triples);
  triples = {};
  const auto t1 = Clock::now();
  if (auto st = r.run(); !st) {
    std::cerr << st.error().message << "\n";
    _exit(1);
  }
  const double reason_ms = ms_since(t1);
  const auto stats = r.stats();
  // Live values: the temperature of machines, one change at a time (as Jena's peer does).
  const kb::TermId temperature = dict.iri(std::string(kb::vocab::kSf) + "temperature");
  std::vector<kb::Triple> targets;
  r.store().match(kb::ValuePattern{kb::kNoTerm, temperature, kb::kNoTerm}, r.store().next_id(),
                  [&](kb::TripleId id) { targets.push_back(r.store().at(id)); });
  std::vector<double> latencies;
  for (int i = 0; i < updates && static_cast<std::size_t>(i) < targets.size(); ++i) {
    const kb::Triple& t = targets[static_cast<std::size_t>(i)];
    const double next = dict.value(t.o)->number + 1.0;
    const kb::TermId value = dict.literal(kb::java_double_string(next), kb::vocab::kXsdDouble);
    const auto u0 = Clock::now();
    auto up = r.set_value(t.s, t.p, value);
    latencies.push_back(ms_since(u0));
    if (!up) {
      std::cerr << up.error().message << "\n";
      _exit(1);
    }
  }
  return {{"load_ms", load_ms},
          {"reason_ms", reason_ms},
          {"inferred", stats.inferred},
          {"input_triples", stats.asserted},
          {"update_median_ms", sf::bench::percentile(latencies, 0.5)},
          {"update_p99_ms", sf::bench::percentile(latencies, 0.99)}};
}

std::string jena_classpath(const std::string& dir) {
  sf::ProcessOptions o;
  o.argv = {"python3", kSource + "/tests/peers/jena/jena_peer.py", "build", dir};
  o.err = sf::Stdio::pipe();
  auto done = sf::Process::run(std::move(o), std::chrono::minutes{30});
  if (!done || !done->status.success()) {
    std::cerr << (done ? done->err : done.error().describe()) << "\n";
    return {};
  }
  std::string out = std::move(done->out);
  while (!out.empty() && out.back() == '\n') {
    out.pop_back();
  }
  return out;
}

// The child roles: generate a data file, or reason over one; each prints one JSON line.
int child_main(const std::vector<std::string>& args) {
  if (args.size() == 3 && args[0] == "--child-generate") {
    kb::Dictionary dict;
    sf::examples::FactoryDataOptions o;
    o.target_triples = std::stoul(args[1]);
    o.seed = 7;
    std::ofstream out(args[2]);
    const bool ok =
        kb::write_rdf(out, dict, sf::examples::generate_factory_data(dict, o), kb::Syntax::ntriples).ok();
    std::cout << nlohmann::json{{"ok", ok}}.dump() << "\n";
    return ok ? 0 : 1;
  }
  if (args.size() == 3 && args[0] == "--child-ours") {
    std::cout << ours(args[1], std::stoi(args[2])).dump() << "\n";
    return 0;
  }
  std::cerr << "bench_knowledge: unknown child role\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string_view(argv[1]).starts_with("--child-")) {
    return child_main({argv + 1, argv + argc});
  }
  std::vector<std::size_t> sizes = {100'000, 1'000'000};
  int updates = 200;
  bool jena = true;
  const double ram_gb =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE)) / 1e9;
  std::string xmx = fmt::format("{}g", std::clamp(static_cast<int>(ram_gb * 0.75), 1, 14));
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::stringstream ss(argv[++i]);
      for (std::string s; std::getline(ss, s, ',');) {
        sizes.push_back(std::stoul(s));
      }
    } else if (a == "--updates" && i + 1 < argc) {
      updates = std::stoi(argv[++i]);
    } else if (a == "--jena-xmx" && i + 1 < argc) {
      xmx = argv[++i];
    } else if (a == "--no-jena") {
      jena = false;
    } else {
      std::cerr << "usage: bench_knowledge [--sizes N,N] [--updates N] [--no-jena] [--jena-xmx SIZE]\n";
      return 2;
    }
  }
  char tmpl[] = "/tmp/bench_knowledge_XXXXXX";
  const std::string dir = mkdtemp(tmpl) != nullptr ? tmpl : "/tmp";
  const std::string classpath = jena ? jena_classpath(dir + "/jena") : std::string();
  if (jena && classpath.empty()) {
    std::cerr << "Jena peer unavailable (java, javac, libapache-jena-java): run with --no-jena\n";
    return 1;
  }
  std::cout << "Forward reasoning over generated candy-factory data (rules: rdfs + owl2rl + candy-factory),\n"
               "ours vs Apache Jena 4.5 GenericRuleReasoner FORWARD_RETE, each in its own process\n";
  std::cout << fmt::format("{:>9} {:>9} | {:>10} {:>10} {:>7} | {:>9} {:>9} {:>6} | {:>10} {:>10}\n",
                           "triples", "inferred", "ours ms", "Jena ms", "speed", "ours MB", "Jena MB", "mem",
                           "upd ours", "upd Jena");
  for (std::size_t size : sizes) {
    const std::string data = fmt::format("{}/factory-{}.nt", dir, size);
    // Generated in a child too, so that the parent (whose memory the children share) stays small.
    const Measured generated =
        measure(self({"--child-generate", std::to_string(size), data}), "", sf::Stream::out);
    if (!generated.ok || !generated.result.value("ok", false)) {
      std::cerr << "generating " << data << " failed\n";
      return 1;
    }
    const Measured a = measure(self({"--child-ours", data, std::to_string(updates)}), "", sf::Stream::out);
    Measured b;
    if (jena) {
      // The peer prints its JSON last on stderr.
      std::vector<std::string> java = {"java"};
      if (!xmx.empty()) {
        java.push_back("-Xmx" + xmx);
      }
      const std::string property = std::string(kb::vocab::kSf) + "temperature";
      java.insert(java.end(), {"-cp",
                               classpath,
                               "JenaReason",
                               "--data",
                               kOntology,
                               "--data",
                               kCatalog,
                               "--data",
                               data,
                               "--rules",
                               kRules[0],
                               "--rules",
                               kRules[1],
                               "--rules",
                               kRules[2],
                               "--stats",
                               "--updates",
                               std::to_string(updates),
                               "--update-property",
                               property});
      b = measure(java, "load_ms", sf::Stream::err);
    }
    if (!a.ok) {
      std::cerr << "our run failed\n";
      return 1;
    }
    if (jena && !b.ok) {
      std::cout << fmt::format(
          "          Jena did not finish at {} triples (heap -Xmx{}; see its output above)\n", size, xmx);
    }
    const double ours_ms = a.result["reason_ms"];
    const double jena_ms = b.ok ? b.result["reason_ms"].get<double>() : 0.0;
    std::cout << fmt::format(
        "{:>9} {:>9} | {:>10.1f} {:>10.1f} {:>6.1f}x | {:>9.1f} {:>9.1f} {:>5.2f} | {:>8.3f}ms {:>8.3f}ms\n",
        a.result["input_triples"].get<std::size_t>(), a.result["inferred"].get<std::size_t>(), ours_ms,
        jena_ms, b.ok ? jena_ms / ours_ms : 0.0, a.peak_mb, b.peak_mb, b.ok ? a.peak_mb / b.peak_mb : 0.0,
        a.result["update_median_ms"].get<double>(), b.ok ? b.result["update_median_ms"].get<double>() : 0.0);
    std::cout << fmt::format(
        "          load (parse) ours {:.0f} ms, Jena {:.0f} ms; Jena inferred {}, heap after GC {:.0f} MB; "
        "update p99 ours {:.3f} ms, Jena {:.3f} ms\n",
        a.result["load_ms"].get<double>(), b.ok ? b.result["load_ms"].get<double>() : 0.0,
        b.ok ? b.result["inferred"].get<std::size_t>() : 0,
        b.ok ? b.result["heap_after_gc_mb"].get<double>() : 0.0, a.result["update_p99_ms"].get<double>(),
        b.ok ? b.result["update_p99_ms"].get<double>() : 0.0);
    std::remove(data.c_str());
    std::cout.flush();
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return 0;
}
