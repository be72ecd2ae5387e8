"""How `ecat run` leaves a segment and finds it again, over a veth wire:
  - Ctrl-C (SIGINT) ends the run the orderly way: drives disabled, segment
    in INIT, exit 0; the next run finds no drive in fault;
  - a master that dies (SIGKILL) leaves the segment in OP: the watchdogs trip
    and the drives fault; the next run resets the faults and runs, exit 0;
  - a drive that faults during the run (it cannot follow: 0x607F written to
    1 count/s with `ecat sdo write`) makes the run exit 1.
"""
import json
import os
import signal
import subprocess
import tempfile
import time

from sftest import Background, VethPair, binary, check, fail, run, run_json, wait_for

SPEC = "smart-controller:1,servo:1"
AXES = 9
FAULT = ("fault", "fault reaction active")

work = tempfile.mkdtemp(prefix="sf-ecat-life-")


def run_master(wire, seconds, extra=()):
    """`ecat run --json` to completion; (exit code, parsed result)."""
    proc = run([binary(), "ecat", "run", "--iface", wire.if_a, "--cycle-us", "1000", "--duration", str(seconds),
                "--json", *extra], ns=wire.ns_a, timeout=180, check_rc=False)
    try:
        return proc.returncode, json.loads(proc.stdout)
    except json.JSONDecodeError:
        fail(f"ecat run printed no JSON (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}")


def started(log):
    with open(log) as f:
        return "slaves in OP" in f.read()


with VethPair("sfl") as wire:
    sim = Background([binary(), "ecat", "sim", "--iface", wire.if_b, "--slaves", SPEC],
                     ns=wire.ns_b, log=os.path.join(work, "sim.log"))
    try:
        time.sleep(0.5)
        check(sim.alive(), "ecat sim is serving the segment")

        # ---- Ctrl-C ------------------------------------------------------
        log = os.path.join(work, "sigint.log")
        master = Background([binary(), "ecat", "run", "--iface", wire.if_a, "--duration", "60"], ns=wire.ns_a, log=log)
        wait_for(lambda: started(log) or not master.alive(), 120, "the run to reach OP")
        time.sleep(1.0)
        master.proc.send_signal(signal.SIGINT)
        rc = master.proc.wait(timeout=30)
        if rc != 0:
            fail(f"ecat run exited {rc} on SIGINT:\n{master.output()[-2000:]}")
        check(rc == 0, "ecat run ends with exit 0 on SIGINT")
        time.sleep(0.5)  # a watchdog would have tripped by now
        rc, after = run_master(wire, 1)
        check(len(after["axes"]) == AXES and not any(a.get("fault_at_start") for a in after["axes"]),
              "after Ctrl-C no drive was left in fault")
        check(rc == 0 and all(a["state"] not in FAULT for a in after["axes"]),
              f"the next run exits 0 with every axis out of fault: {[a['state'] for a in after['axes']]}")

        # ---- a master that dies ------------------------------------------
        log = os.path.join(work, "killed.log")
        master = Background([binary(), "ecat", "run", "--iface", wire.if_a, "--duration", "60"], ns=wire.ns_a, log=log)
        wait_for(lambda: started(log) or not master.alive(), 120, "the run to reach OP")
        time.sleep(1.0)
        master.proc.kill()
        master.proc.wait()
        time.sleep(0.5)  # the watchdogs trip, the drives fault
        statusword = run_json([binary(), "ecat", "sdo", "read", "--iface", wire.if_a, "--slave", "1", "0x6041",
                               "--json"], ns=wire.ns_a)
        check(int(statusword["value"].split()[0]) & 0x004F == 0x0008,
              f"after SIGKILL the servo is in fault (statusword {statusword['value']})")
        rc, after = run_master(wire, 2)
        check(all(a["state"] not in FAULT for a in after["axes"]),
              f"the next run resets the faults: {[a['state'] for a in after['axes']]}")
        check(rc == 0 and after.get("problems") == [], f"and exits 0: {after.get('problems')}")

        # ---- a drive that faults -----------------------------------------
        run([binary(), "ecat", "sdo", "write", "--iface", wire.if_a, "--slave", "1", "0x607F", "0", "1"],
            ns=wire.ns_a)
        rc, faulted = run_master(wire, 3)
        check(rc == 1, f"a run in which a drive faults exits 1 ({rc})")
        check("axis 1.0 ended in fault" in faulted.get("problems", []),
              f"the problem names the axis: {faulted.get('problems')}")
        check(next(a for a in faulted["axes"] if a["slave"] == 1).get("fault"), "the servo's axis is reported in fault")
    finally:
        sim.stop()
subprocess.run(["rm", "-rf", work])
