"""The knowledge layer's reasoner against Apache Jena (Debian libapache-jena-java): for every
rule file in rules/ and for all of them together, over the candy-factory ontology, the
prototype line and generated factory data, `smartfactory kb reason` infers exactly the triples
that Jena's GenericRuleReasoner in FORWARD_RETE mode puts in its deductions graph (blank nodes
compared up to renaming)."""
import glob
import os
import subprocess
import sys
import tempfile

from sftest import binary, check, fail, run, skip

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "peers", "jena"))
import jena_peer  # noqa: E402
import ntriples  # noqa: E402

why = jena_peer.missing()
if why:
    skip(why)

work = tempfile.mkdtemp(prefix="kb_jena_")
classpath = jena_peer.build(os.path.join(work, "jena"))
data = os.path.join(work, "factory.nt")
run([binary(), "kb", "generate", "--triples", os.environ.get("KB_JENA_TRIPLES", "20000"), "--seed", "7",
     "-o", data])
inputs = [os.path.join(ROOT, "ontology", "candy-factory.ttl"), os.path.join(ROOT, "ontology", "prototype-line.ttl"),
          os.path.join(ROOT, "ontology", "prototype-snapshot.ttl"), data]
rule_files = sorted(glob.glob(os.path.join(ROOT, "rules", "*.rules")))
check(len(rule_files) >= 3, f"rule files to compare: {[os.path.basename(f) for f in rule_files]}")


def ours(rules, out):
    args = [binary(), "kb", "reason", "--ontology", inputs[0]]
    for f in inputs[1:]:
        args += ["--data", f]
    for r in rules:
        args += ["--rules", r]
    run(args + ["-o", out], timeout=600)
    with open(out) as f:
        return ntriples.parse(f.read())


def jena(rules, out):
    args = ["java", "-cp", classpath, "JenaReason"]
    for f in inputs:
        args += ["--data", f]
    for r in rules:
        args += ["--rules", r]
    proc = subprocess.run(args + ["--out", out], capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        fail(f"Jena failed:\n{proc.stderr[-3000:]}")
    with open(out) as f:
        return ntriples.parse(f.read())


cases = [[f] for f in rule_files] + [rule_files]
for rules in cases:
    name = "+".join(os.path.basename(r) for r in rules)
    stem = name.replace("+", "_")
    a = ours(rules, os.path.join(work, stem + ".ours.nt"))
    b = jena(rules, os.path.join(work, stem + ".jena.nt"))
    diff = ntriples.difference(a, b)
    check(not diff and len(a) > 0,
          f"{name}: {len(a)} inferred triples, Jena {len(b)}" + ("" if not diff else "\n" + "\n".join(diff)))
