"""Contract Net negotiation between separate OS processes over DDS on
loopback (paper section IV.B): machines, conveyors and products each run as
`smartfactory agent ...`. Checks that every entity has the paper's DDS layout
(as it reports itself and as the built-in topics show it to others), that
every operation is awarded once, confirmed and done, and that each route
connects the product's previous place to the machine that won.
"""
import json
import os
import shutil
import tempfile
import time
import uuid

from sftest import Background, binary, check, fail, run, wait_for

PARTITION = f"cnp-it-{uuid.uuid4().hex[:8]}"
COMMON = ["--partition", PARTITION, "--json"]
MACHINES = {"M1": "OP1", "M2": "OP1,OP2", "M3": "OP2,OP3", "M4": "OP3"}
CONVEYORS = [("C1", "Input", "M1"), ("C2", "Input", "M2"), ("C3", "M1", "M2"), ("C4", "M1", "M3"),
             ("C5", "M2", "M3"), ("C6", "M2", "M4"), ("C7", "M3", "M4")]
PRODUCTS = {"P": ("OP1,OP2,OP3", 3, "Input"), "Q": ("OP2,OP3", 2, "M1")}


def events(text):
    out = []
    for line in text.splitlines():
        if line.startswith("{"):
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                fail(f"not JSON: {line}")
    return out


def topics(endpoints):
    return sorted(e["topic"] for e in endpoints)


def check_layout(name, evs, expected):
    layouts = [e for e in evs if e["event"] == "layout"]
    check(len(layouts) == 1, f"{name} reports its layout once")
    got = {p["domain"]: (topics(p["readers"]), topics(p["writers"])) for p in layouts[0]["participants"]}
    check(got == expected, f"{name} layout {got} == {expected}")


def expected_product_layout(ops):
    ops = ops.split(",")
    return {10: (sorted(f"{o}_BID" for o in ops), sorted([f"{o}_ANNOUNCE" for o in ops] + [f"{o}_AWARD" for o in ops])),
            11: (["INFORM"], ["REQUEST"])}


def expected_machine_layout(ops):
    ops = ops.split(",")
    return {10: (sorted([f"{o}_ANNOUNCE" for o in ops] + [f"{o}_AWARD" for o in ops]), sorted(f"{o}_BID" for o in ops))}


def main():
    sf = binary()
    tmp = tempfile.mkdtemp(prefix="cnp-it-")
    agents = {}
    try:
        for name, ops in MACHINES.items():
            agents[name] = Background([sf, "agent", "machine", "--name", name, "--ops", ops, "--work-ms", "30",
                                       "--layout"] + COMMON, log=os.path.join(tmp, f"{name}.log"))
        for name, a, b in CONVEYORS:
            agents[name] = Background([sf, "agent", "conveyor", "--name", name, "--from", a, "--to", b,
                                       "--transit-ms", "500", "--layout"] + COMMON, log=os.path.join(tmp, f"{name}.log"))
        products = {}
        for name, (ops, count, start) in PRODUCTS.items():
            products[name] = Background([sf, "agent", "product", "--name", name, "--ops", ops, "--count", str(count),
                                         "--start", start, "--timeout", "60", "--layout"] + COMMON,
                                        log=os.path.join(tmp, f"{name}.log"))
        for name, p in products.items():
            try:
                p.proc.wait(timeout=90)
            except Exception:
                fail(f"product {name} did not finish:\n{p.output()}")
            check(p.proc.returncode == 0, f"product process {name} exits 0\n{p.output() if p.proc.returncode else ''}")

        # The layout as every other participant sees it (built-in topics), while all agents run.
        seen = json.loads(run([sf, "cnp", "layout", "--partition", PARTITION, "--json"]).stdout)
        by_name = {}
        for p in seen:
            by_name.setdefault(p["participant"], {})[p["domain"]] = (topics(p["readers"]), topics(p["writers"]))
        for name, ops in MACHINES.items():
            check(by_name.get(f"machine/{name}") == expected_machine_layout(ops), f"discovered layout of machine {name}")
        for name, _, _ in CONVEYORS:
            check(by_name.get(f"conveyor/{name}") == {11: (["REQUEST"], ["INFORM"])}, f"discovered layout of {name}")
    finally:
        for a in agents.values():
            a.stop()

    outputs = {name: events(a.output()) for name, a in {**agents, **products}.items()}
    for name, ops in MACHINES.items():
        check_layout(name, outputs[name], expected_machine_layout(ops))
    for name, _, _ in CONVEYORS:
        check_layout(name, outputs[name], {11: (["REQUEST"], ["INFORM"])})
    for name, (ops, _, _) in PRODUCTS.items():
        check_layout(name, outputs[name], expected_product_layout(ops))

    # Who worked what, from the machines' own reports.
    started, done = {}, {}
    for name in MACHINES:
        for e in outputs[name]:
            if e["event"] == "start":
                started.setdefault(e["conversation"], []).append(name)
            if e["event"] == "done":
                done.setdefault(e["conversation"], []).append(name)

    total = 0
    for name, (ops, count, start) in PRODUCTS.items():
        evs = outputs[name]
        summary = [e for e in evs if e["event"] == "summary"]
        check(summary and summary[0]["succeeded"] == count and summary[0]["failed"] == 0,
              f"{name}: all {count} products succeeded")
        for i in range(1, count + 1):
            product = f"{name}-{i}" if count > 1 else name
            mine = [e for e in evs if e.get("product") == product]
            awards = [e for e in mine if e["event"] == "award"]
            steps = [e for e in mine if e["event"] == "done"]
            routes = [e for e in mine if e["event"] == "route"]
            check([a["operation"] for a in awards] == ops.split(","), f"{product}: one award per operation, in order")
            check([s["operation"] for s in steps] == ops.split(","), f"{product}: every operation done once")
            at = start
            for award, step, route in zip(awards, steps, routes):
                conv = award["conversation"]
                total += 1
                check(award["contractor"] in MACHINES and award["operation"] in MACHINES[award["contractor"]].split(","),
                      f"{conv}: awarded to {award['contractor']}, which offers {award['operation']}")
                check(started.get(conv) == [award["contractor"]], f"{conv}: worked by exactly {award['contractor']}")
                check(done.get(conv) == [award["contractor"]], f"{conv}: INFORM-DONE from exactly {award['contractor']}")
                check(route["from"] == at and route["to"] == award["contractor"],
                      f"{product}: route {route['from']} -> {route['to']} leads from {at} to {award['contractor']}")
                hop = at
                for seg in route["segments"]:
                    check(seg["from"] == hop, f"{product}: segment {seg['conveyor']} starts where the last ended")
                    hop = seg["to"]
                check(hop == award["contractor"], f"{product}: segments end at {award['contractor']}")
                at = award["contractor"]
    check(total == 3 * 3 + 2 * 2, f"{total} negotiations checked")
    check_exit_with_parent(sf, tmp)
    check_bench_processes(sf, tmp)
    shutil.rmtree(tmp, ignore_errors=True)  # kept only when a check failed


def alive(pid):
    """True while the process exists and is not a zombie."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def check_exit_with_parent(sf, tmp):
    """An agent started with --exit-with-parent stops when the process that started it dies (as the
    contractor processes of `cnp bench` do when the benchmark is killed)."""
    ready = os.path.join(tmp, "orphan.log")
    # The shell starts the machine, waits until it is ready, prints its pid and exits.
    script = (f'"$0" agent machine --name orphan --ops OP1 --partition {PARTITION}-orphan --json '
              f'--exit-with-parent > "{ready}" 2>&1 & pid=$!; '
              f'while ! grep -q ready "{ready}"; do sleep 0.05; done; echo $pid')
    pid = int(run(["sh", "-c", script, sf], timeout=60).stdout.strip())
    deadline = time.monotonic() + 20
    while alive(pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    if alive(pid):
        os.kill(pid, 9)
        fail(f"machine {pid} still runs after its parent exited")
    check(True, "an agent with --exit-with-parent stops when its parent exits")


def children_of(pid):
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        out.append(int(entry))
            except (OSError, ValueError, IndexError):
                pass
    return out


def scheduling_policy(pid):
    """The policy number of /proc/PID/sched (0 SCHED_OTHER, 3 SCHED_BATCH); None once it exited."""
    try:
        with open(f"/proc/{pid}/sched") as f:
            for line in f:
                if line.startswith("policy"):
                    return int(line.split(":")[1])
    except OSError:
        return None
    return None


def command_line(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            return [a.decode() for a in f.read().split(b"\0") if a]
    except OSError:
        return []


def option(args, name):
    """The value after `name` in a command line, or None."""
    return args[args.index(name) + 1] if name in args[:-1] else None


def check_bench_processes(sf, tmp):
    """`cnp bench --processes` measures every negotiation it was asked for with each contractor in
    its own process; those processes run under SCHED_BATCH (the default --contractor-sched) with
    the benchmark's liveliness lease and network interface."""
    log = os.path.join(tmp, "bench.log")
    n = 3
    bench = Background([sf, "cnp", "bench", "--contractors", str(n), "--negotiations", "200", "--processes",
                        "--no-ddsperf", "--lease-ms", "1500", "--interface", "lo", "--json"], log=log)
    wait_for(lambda: len(children_of(bench.proc.pid)) >= n or not bench.alive(), 60,
             "the benchmark's contractor processes")
    children = children_of(bench.proc.pid)
    policies = [scheduling_policy(pid) for pid in children]
    check(len(policies) == n and all(p == 3 for p in policies),
          f"the {n} contractor processes run under SCHED_BATCH (policies {policies})")
    for pid in children:
        args = command_line(pid)
        check(option(args, "--lease-ms") == "1500" and option(args, "--interface") == "lo",
              f"contractor {pid} got the benchmark's lease and interface: {args}")
    try:
        bench.proc.wait(timeout=180)
    except Exception:
        bench.stop()
        fail("cnp bench --processes did not finish within 180 s")
    rc = bench.stop()
    lines = [l for l in bench.output().splitlines() if l.startswith("{")]
    check(rc == 0 and len(lines) == 1, f"cnp bench exited {rc} with one JSON result")
    result = json.loads(lines[0])
    check(result["processes"] and result["contractors"] == n and result["contractor_sched"] == "batch",
          f"the result says {n} contractor processes under batch scheduling: {result}")
    check(result["latency_us"]["samples"] == 200 and result["failed"] == 0 and result["sequential_per_s"] > 0
          and result["pipelined_per_s"] > 0, "every negotiation of both phases was measured, none failed")


if __name__ == "__main__":
    main()
