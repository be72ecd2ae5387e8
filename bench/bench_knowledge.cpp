// Reasoning over generated candy-factory data (libs/knowledge) next to Apache Jena's forward
// RETE engine (GenericRuleReasoner, FORWARD_RETE) in the same run: the same ontology, data and
// rule files (rules/rdfs.rules, owl2rl.rules, candy-factory.rules), each engine in its own
// process so that its peak resident memory (getrusage ru_maxrss) is its own. Then the latency of
// one live-value change (a machine's temperature) maintained incrementally, in both.
//
//   bench_knowledge [--sizes 100000,1000000] [--updates 200] [--no-jena] [--jena-xmx 16g]
//
// --jena-xmx sets the JVM's maximum heap (default: three quarters of the machine's memory, at
// most 14g; the JVM's own default of a quarter is too small for Jena's RETE network at a
// million triples).
//
// Times: reasoning only (closure from loaded data); "load" is parsing the N-Triples file.
#include <sys/resource.h>
#include <sys/wait.h>
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

#include "sf/knowledge/factory_data.hpp"
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

// Runs fn in a child process; fn writes a JSON line to the pipe. The parent reads it and the
// child's peak RSS from wait4().
template <typename F>
Measured in_child(F&& fn) {
  int fds[2];
  if (pipe(fds) != 0) {
    return {};
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const std::string line = fn().dump() + "\n";
    (void)!write(fds[1], line.data(), line.size());
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  std::array<char, 4096> buf{};
  for (ssize_t n; (n = read(fds[0], buf.data(), buf.size())) > 0;) {
    text.append(buf.data(), static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  Measured m;
  m.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  m.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && !text.empty();
  if (m.ok) {
    m.result = nlohmann::json::parse(text, nullptr, false);
  }
  return m;
}

// Runs a command with its stderr captured (for the Java peer).
Measured command(const std::string& cmd) {
  return in_child([&] {
    const std::string full = cmd + " 2>&1 >/dev/null";
    FILE* p = popen(full.c_str(), "r");
    std::string out;
    std::array<char, 4096> buf{};
    for (std::size_t n; p != nullptr && (n = fread(buf.data(), 1, buf.size(), p)) > 0;) {
      out.append(buf.data(), n);
    }
    const int rc = p == nullptr ? -1 : pclose(p);
    // The last line of the peer's stderr is its JSON; the child's rusage includes the JVM.
    const auto start = out.rfind("{\"load_ms\"");
    nlohmann::json j = start == std::string::npos ? nlohmann::json{}
                                                  : nlohmann::json::parse(out.substr(start), nullptr, false);
    if (rc != 0 || j.is_discarded() || j.is_null()) {
      std::cerr << out.substr(out.size() > 2000 ? out.size() - 2000 : 0) << "\n";
      _exit(1);
    }
    return j;
  });
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) {
    return 0;
  }
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
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
          {"update_median_ms", percentile(latencies, 0.5)},
          {"update_p99_ms", percentile(latencies, 0.99)}};
}

std::string jena_classpath(const std::string& dir) {
  const std::string cmd = fmt::format("python3 {}/tests/peers/jena/jena_peer.py build {}", kSource, dir);
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  for (std::size_t n; p != nullptr && (n = fread(buf.data(), 1, buf.size(), p)) > 0;) {
    out.append(buf.data(), n);
  }
  if (p == nullptr || pclose(p) != 0) {
    return {};
  }
  while (!out.empty() && out.back() == '\n') {
    out.pop_back();
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
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
    const Measured generated = in_child([&] {
      kb::Dictionary dict;
      kb::FactoryDataOptions o;
      o.target_triples = size;
      o.seed = 7;
      std::ofstream out(data);
      const bool ok = kb::write_rdf(out, dict, kb::generate_factory_data(dict, o), kb::Syntax::ntriples).ok();
      return nlohmann::json{{"ok", ok}};
    });
    if (!generated.ok || !generated.result.value("ok", false)) {
      std::cerr << "generating " << data << " failed\n";
      return 1;
    }
    const Measured a = in_child([&] { return ours(data, updates); });
    Measured b;
    if (jena) {
      b = command(fmt::format(
          "java {} -cp '{}' JenaReason --data {} --data {} --data {} --rules {} --rules {} --rules {} --stats "
          "--updates {} --update-property {}temperature",
          xmx.empty() ? std::string() : "-Xmx" + xmx, classpath, kOntology, kCatalog, data, kRules[0], kRules[1],
          kRules[2], updates, kb::vocab::kSf));
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
