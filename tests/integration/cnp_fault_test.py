"""Contract Net under faults, across OS processes over DDS (paper section IV.B).

10 000 negotiations: 4 product processes x 625 products x 4 operations, 8
machine processes with randomised work times. Machines are killed with
SIGKILL (no goodbye on the wire) right after bidding, right after receiving
an award, while working, and at random moments; each dead machine is replaced
by a new process of the same kind. Afterwards:

- every product finished, every (product, operation) was done exactly once
  (no operation lost);
- no operation was worked by two machines at the same time: the machines'
  work intervals (start .. done / abort / death) for one conversation never
  overlap;
- the machine a product credits with an operation reported it done.
"""
import json
import os
import shutil
import random
import signal
import tempfile
import time
import uuid

from sftest import Background, binary, check, fail

OPS = ["OP1", "OP2", "OP3", "OP4"]
KINDS = [["OP1", "OP2"], ["OP2", "OP3"], ["OP3", "OP4"], ["OP4", "OP1"]] * 2
PRODUCT_PROCESSES = 4
PRODUCTS_EACH = 625
PARALLEL = 40
LEASE_MS = 1500
BUDGET_S = 170
PARTITION = f"cnp-fault-{uuid.uuid4().hex[:8]}"
COMMON = ["--partition", PARTITION, "--json", "--machining-domain", "12", "--conveying-domain", "13"]


def events(path):
    out = []
    with open(path) as f:
        for line in f:
            if line.startswith("{"):
                try:
                    out.append(json.loads(line))
                except json.JSONDecodeError:
                    pass  # a line cut by SIGKILL
    return out


class Machines:
    def __init__(self, sf, tmp, rng):
        self.sf, self.tmp, self.rng = sf, tmp, rng
        self.live = {}       # name -> (Background, ops)
        self.dead = {}       # name -> time of death (ns, UTC)
        self.logs = {}
        self.serial = 0
        self.kills = {"bid": 0, "award": 0, "confirm": 0, "external": 0}

    def start(self, ops, hook=None):
        self.serial += 1
        name = f"M{self.serial}"
        args = [self.sf, "--log-level", "warn", "agent", "machine", "--name", name, "--ops", ",".join(ops),
                "--work-ms", "2", "--jitter-ms", "8", "--capacity", "64", "--lease-ms", str(LEASE_MS),
                "--seed", str(self.serial)] + COMMON
        if hook:
            args += ["--kill-after", hook]
        self.logs[name] = os.path.join(self.tmp, f"{name}.log")
        self.live[name] = (Background(args, log=self.logs[name]), ops)
        return name

    def reap(self):
        """Replaces machines that died (by their hook or by us) with fresh ones."""
        for name, (bg, ops) in list(self.live.items()):
            if bg.alive():
                continue
            bg.stop()
            del self.live[name]
            self.dead[name] = time.time_ns()
            killed = [e for e in events(self.logs[name]) if e["event"] == "killed"]
            if killed:
                self.kills[killed[0]["after"]] += 1
                self.dead[name] = killed[0]["t"]
            self.start(ops, self.random_hook())

    def random_hook(self):
        if sum(self.kills.values()) >= 24:
            return None
        return self.rng.choice([None, f"bid:{self.rng.randint(50, 400)}", f"award:{self.rng.randint(20, 200)}",
                                f"confirm:{self.rng.randint(20, 200)}"])

    def kill_one(self):
        name = self.rng.choice(sorted(self.live))
        bg, _ = self.live[name]
        os.kill(bg.proc.pid, signal.SIGKILL)
        bg.proc.wait()
        self.kills["external"] += 1
        self.dead[name] = time.time_ns()

    def stop_all(self):
        for bg, _ in self.live.values():
            bg.stop()


def work_intervals(machines):
    """conversation -> [(start, end, machine)] from every machine's log."""
    intervals = {}
    for name, path in machines.logs.items():
        open_jobs = {}
        for e in events(path):
            if e["event"] == "start":
                open_jobs[e["conversation"]] = e["t"]
            elif e["event"] in ("done", "failure", "abort") and e["conversation"] in open_jobs:
                intervals.setdefault(e["conversation"], []).append((open_jobs.pop(e["conversation"]), e["t"], name))
        end_of_life = machines.dead.get(name, time.time_ns())
        for conv, t0 in open_jobs.items():
            intervals.setdefault(conv, []).append((t0, end_of_life, name))
    return intervals


def main():
    sf = binary()
    rng = random.Random(int(os.environ.get("SF_SEED", "7")))
    tmp = tempfile.mkdtemp(prefix="cnp-fault-")
    machines = Machines(sf, tmp, rng)
    products = {}
    started = time.monotonic()
    try:
        for i, ops in enumerate(KINDS):
            machines.start(ops, machines.random_hook() if i % 2 == 0 else None)
        for i in range(PRODUCT_PROCESSES):
            name = f"P{i}"
            products[name] = Background(
                [sf, "--log-level", "warn", "agent", "product", "--name", name, "--ops", ",".join(OPS),
                 "--count", str(PRODUCTS_EACH), "--parallel", str(PARALLEL), "--no-route", "--bid-ms", "1000",
                 "--confirm-ms", "600", "--max-rounds", "0", "--timeout", str(BUDGET_S)] + COMMON,
                log=os.path.join(tmp, f"{name}.log"))
        next_external = time.monotonic() + rng.uniform(3, 8)
        while any(p.alive() for p in products.values()):
            if time.monotonic() - started > BUDGET_S + 20:
                fail("products did not finish in time")
            machines.reap()
            if time.monotonic() > next_external and machines.kills["external"] < 6:
                machines.kill_one()
                next_external = time.monotonic() + rng.uniform(3, 8)
            time.sleep(0.2)
        machines.reap()
    finally:
        machines.stop_all()
        for p in products.values():
            p.stop()
    elapsed = time.monotonic() - started
    print(f"run took {elapsed:.1f} s; kills: {machines.kills}", flush=True)

    credited = {}  # conversation -> machine the product credits
    negotiations = 0
    for name, p in products.items():
        evs = events(p.log_path)
        summary = [e for e in evs if e["event"] == "summary"]
        check(p.proc.returncode == 0 and summary and summary[0]["succeeded"] == PRODUCTS_EACH,
              f"{name}: all {PRODUCTS_EACH} products finished ({summary[0] if summary else 'no summary'})")
        done = [e for e in evs if e["event"] == "done"]
        pairs = {(e["product"], e["operation"]) for e in done}
        check(len(done) == len(pairs) == PRODUCTS_EACH * len(OPS), f"{name}: every operation done exactly once")
        for e in done:
            credited[e["conversation"]] = e["contractor"]
        negotiations += len(done)
    check(negotiations >= 10_000, f"{negotiations} negotiations")
    kills = machines.kills
    check(kills["bid"] + kills["award"] + kills["confirm"] + kills["external"] >= 6 and kills["external"] > 0,
          f"machines were killed after bidding, after an award, while working and at random: {kills}")

    intervals = work_intervals(machines)
    overlaps = []
    for conv, spans in intervals.items():
        spans.sort()
        for (s0, e0, m0), (s1, e1, m1) in zip(spans, spans[1:]):
            if s1 < e0 and m0 != m1:
                overlaps.append((conv, m0, m1))
    check(not overlaps, f"no operation worked by two machines at once ({len(overlaps)} overlaps: {overlaps[:5]})")
    done_by = {}
    for name, path in machines.logs.items():
        for e in events(path):
            if e["event"] == "done":
                done_by.setdefault(e["conversation"], set()).add(name)
    wrong = [c for c, m in credited.items() if m not in done_by.get(c, set())]
    check(not wrong, f"every credited machine reported the operation done ({len(wrong)} not: {wrong[:5]})")
    renegotiated = sum(1 for spans in intervals.values() if len({m for _, _, m in spans}) > 1)
    print(f"{renegotiated} operations moved to another machine after a fault", flush=True)
    check(renegotiated > 0, "faults did force renegotiations")
    shutil.rmtree(tmp, ignore_errors=True)  # kept only when a check failed


if __name__ == "__main__":
    main()
