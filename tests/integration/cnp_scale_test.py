"""Many DDS participants on one host with the generated loopback configuration
(no system settings touched): 56 machine processes and a product process meet
in the MachiningDomain, everyone discovers everyone, and negotiations work.
"""
import json
import os
import shutil
import tempfile
import time
import uuid

from sftest import Background, binary, check, run, wait_for

MACHINES = 56
PARTITION = f"cnp-scale-{uuid.uuid4().hex[:8]}"
COMMON = ["--partition", PARTITION, "--machining-domain", "14", "--conveying-domain", "15"]


def machines_seen(sf):
    seen = json.loads(run([sf, "cnp", "layout", "--settle-ms", "1000", "--json"] + COMMON).stdout)
    return {p["participant"] for p in seen if p["participant"].startswith("machine/")}


def main():
    sf = binary()
    tmp = tempfile.mkdtemp(prefix="cnp-scale-")
    machines = []
    try:
        for i in range(MACHINES):
            machines.append(Background([sf, "--log-level", "warn", "agent", "machine", "--name", f"M{i}",
                                        "--ops", "OP1", "--work-ms", "1"] + COMMON,
                                       log=os.path.join(tmp, f"M{i}.log")))
        wait_for(lambda: len(machines_seen(sf)) == MACHINES, 120, f"{MACHINES} machines to be discovered")
        check(all(m.alive() for m in machines), f"all {MACHINES} machine processes run")
        started = time.monotonic()
        out = run([sf, "--log-level", "warn", "agent", "product", "--name", "P", "--ops", "OP1", "--count", "50",
                   "--no-route", "--json", "--timeout", "60"] + COMMON, timeout=90)
        events = [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
        awards = [e for e in events if e["event"] == "award"]
        summary = [e for e in events if e["event"] == "summary"][0]
        check(summary["succeeded"] == 50 and summary["failed"] == 0, f"50 products finished: {summary}")
        check(len(awards) == 50 and len({a["conversation"] for a in awards}) == 50, "one award per negotiation")
        print(f"50 negotiations against {MACHINES} machine processes in {time.monotonic() - started:.1f} s",
              flush=True)
    finally:
        for m in machines:
            m.stop()
    shutil.rmtree(tmp, ignore_errors=True)  # kept only when a check failed


if __name__ == "__main__":
    main()
