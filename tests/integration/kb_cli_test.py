"""`smartfactory kb`: violations of the prototype line with their explanations, errors that
name file, line and column without printing any result, the derivation limit, and
reproducible generated data."""
import filecmp
import os
import re
import tempfile

from sftest import binary, check, run, run_json

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ONTOLOGY = os.path.join(ROOT, "ontology", "candy-factory.ttl")
LINE = os.path.join(ROOT, "ontology", "prototype-line.ttl")
SNAPSHOT = os.path.join(ROOT, "ontology", "prototype-snapshot.ttl")
RULES = [os.path.join(ROOT, "rules", r) for r in ("rdfs.rules", "owl2rl.rules", "candy-factory.rules")]
work = tempfile.mkdtemp(prefix="kb_cli_")


def reason(extra, data=(LINE, SNAPSHOT), rules=RULES, check_rc=True):
    args = [binary(), "kb", "reason", "--ontology", ONTOLOGY]
    for d in data:
        args += ["--data", d]
    for r in rules:
        args += ["--rules", r]
    return run(args + extra, check_rc=check_rc, timeout=120)


def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


# --- violations of the prototype line (ontology/prototype-line.ttl), explained --------------
out = run_json([binary(), "kb", "reason", "--ontology", ONTOLOGY, "--data", LINE, "--data", SNAPSHOT] +
               sum([["--rules", r] for r in RULES], []) + ["--json", "--explain"])
by = {}
for v in out["violations"]:
    by.setdefault(v["subject"].rsplit("/", 1)[-1].rstrip(">"), []).append(v)
denso = [v for v in by.get("Denso", []) if v["rule"] == "temperatureHigh"]
check(len(denso) == 1 and denso[0]["message"] == "temperature 74.0 above the maximum 70.0",
      f"the DENSO arm at 74.0 degrees violates its maximum: {denso}")
check(any("temperature> \"74.0\"" in m for m in denso[0]["matched"]) and
      any("maxTemperature> \"70.0\"" in m for m in denso[0]["matched"]),
      f"the explanation lists the matched triples: {denso[0]['matched']}")
check(re.search(r"candy-factory\.rules:\d+:1$", denso[0]["at"]) is not None,
      f"the explanation names the rule's place: {denso[0]['at']}")
check(any(v["rule"] == "overspeed" for v in by.get("Conveyor3", [])), "conveyor 3 runs too fast")
check(any(v["rule"] == "fault" and "box jam" in v["message"] for v in by.get("Downloader", [])),
      "the downloader is faulted")
check(any(v["rule"] == "alarmRaised" for v in by.get("Downloader", [])), "the downloader's jam alarm is open")
check(any(v["rule"] == "contentMismatch" and "gummy bear: ordered 6, the box holds 5" in v["message"]
          for v in by.get("Box1", [])), f"box 1 lacks a gummy bear: {by.get('Box1')}")
check(any(v["rule"] == "cannotPerform" and "pick and place" in v["message"] for v in by.get("Load2", [])),
      "the uploader cannot pick and place")
check("Load1" not in by and "ScaraRobot1" not in by and "Toshiba" not in by, "no false alarms")
status = [t for t in out["inferred"] if "Download1" in t and "status" in t]
check(status and "awaiting negotiation" in status[0], f"the unassigned download awaits negotiation: {status}")
check(len(out["derivations"]) == len(out["inferred"]) and all(d["rule"] for d in out["derivations"]),
      "--explain gives every inferred triple its rule")
typed = [t for t in out["inferred"] if "ScaraRobot1>" in t and "#Machine>" in t]
check(typed, "RDFS/OWL: ScaraRobot1 is a Machine")

text = reason(["--explain"]).stdout
check("# rule temperatureHigh" in text and "# violation: <http://smartfactory.example/prototype/Denso>" in text,
      "text output: explanations and violations as N-Triples comments")

# --- bad input: file:line:column, nothing printed ------------------------------------------
bad_ttl = write("bad.ttl", "@prefix sf: <http://smartfactory.example/ontology/candy#> .\n"
                           "sf:a sf:temperature \"41.5\"^^<http://www.w3.org/2001/XMLSchema#double> .\n"
                           "sf:b sf:temperature 12 ;\n  sf:state \"running .\n")
r = reason([], data=(LINE, SNAPSHOT, bad_ttl), check_rc=False)
check(r.returncode != 0 and f"{bad_ttl}:4:" in r.stderr and r.stdout == "",
      f"malformed Turtle: exit {r.returncode}, error {r.stderr.strip()!r}, nothing on stdout")
broken = "[broken: (?m sf:temperature ?t) greaterThan(?t) -> (?m sf:hot 'yes')]"
bad_rules = write("bad.rules", "@prefix sf: <http://smartfactory.example/ontology/candy#>.\n"
                               "[ok: (?m sf:temperature ?t) -> (?m sf:seen 'yes')]\n" + broken + "\n")
r = reason([], rules=RULES + [bad_rules], check_rc=False)
where = f"{bad_rules}:3:{broken.index('greaterThan') + 1}:"
check(r.returncode != 0 and where in r.stderr and "greaterThan" in r.stderr and r.stdout == "",
      f"malformed rules: {r.stderr.strip()!r}")

# --- runaway rules stop at the limit -------------------------------------------------------
runaway = write("runaway.rules", "@prefix sf: <http://smartfactory.example/ontology/candy#>.\n"
                                 "[chain: (?x sf:connectedTo ?y) -> (?y sf:connectedTo ?fresh)]\n")
r = reason(["--max-derived", "5000"], rules=[runaway], check_rc=False)
check(r.returncode != 0 and "derivation limit" in r.stderr and "'chain'" in r.stderr and "5000" in r.stderr,
      f"a rule that never terminates stops at --max-derived: {r.stderr.strip()!r}")

# --- generated data is reproducible ----------------------------------------------------------
a, b = os.path.join(work, "a.nt"), os.path.join(work, "b.nt")
for path in (a, b):
    run([binary(), "kb", "generate", "--triples", "5000", "--seed", "3", "-o", path])
check(filecmp.cmp(a, b, shallow=False), "the same seed generates the same data")
r = reason(["--json"], data=(a,))
check('"violations"' in r.stdout, "generated data reasons")
