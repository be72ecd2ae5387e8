"""Helpers for smartfactory's integration tests: the binary, network
namespaces with veth pairs, background processes, and plain assertions.

Tests run as scripts under ctest; exit code 77 means "skipped" (not root,
no namespaces), any other non-zero exit is a failure with a message.
"""
import collections
import ctypes
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import uuid

SKIP = 77


def binary():
    path = os.environ.get("SF_BIN")
    if not path or not os.path.exists(path):
        fail(f"SF_BIN does not name the smartfactory binary: {path!r}")
    return path


def keep_on_failure(name, directory):
    """Copies a failed test's working directory (its processes' logs and events) next to the
    binary under test-artifacts/NAME, so a failure in CI can be read afterwards."""
    target = os.path.join(os.path.dirname(os.path.abspath(binary())), "..", "test-artifacts", name)
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(directory, target, ignore=shutil.ignore_patterns("*.sock", "*.db-wal", "*.db-shm"),
                    ignore_dangling_symlinks=True, dirs_exist_ok=True)
    print(f"note: the run is kept in {os.path.normpath(target)}", flush=True)


def source_dir():
    path = os.environ.get("SF_SOURCE_DIR") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return path


def node_peer(script):
    """The command that runs one of tests/peers/*/ with node, or skips when node-opcua is absent."""
    if shutil.which("node") is None:
        skip("node is not installed (scripts/setup installs it)")
    root = source_dir()
    if not os.path.isdir(os.path.join(root, "node_modules", "node-opcua")):
        skip("node-opcua is not installed (scripts/setup runs npm ci)")
    return ["node", os.path.join(root, "tests", "peers", script)]


def node_peer_result(script, args, timeout=120):
    """Runs a node peer (see node_peer) and returns the JSON object on its last line starting with '{'."""
    proc = run(node_peer(script) + list(args), timeout=timeout)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
    if not lines:
        fail(f"{script} {' '.join(args)} printed no result:\n{proc.stdout}\n{proc.stderr}")
    return json.loads(lines[-1])


def wait_for_line(background, prefix, timeout):
    """Waits until the background process's log has a line starting with prefix; returns it."""
    found = []

    def has_line():
        for line in background.output().splitlines():
            if line.startswith(prefix):
                found.append(line)
                return True
        if not background.alive():
            fail(f"process exited before printing '{prefix}':\n{background.output()}")
        return False

    wait_for(has_line, timeout, f"a line starting with '{prefix}'")
    return found[0]


def json_events(text, kind=None):
    """The JSON lines of a process's output (lines starting with '{'), only those whose "event" is
    kind when given; a line that is not JSON fails the test. A last line without its newline is left
    for the next read: the process may be writing it (a long line reaches a log file in pieces)."""
    out = []
    lines = text.splitlines()
    if text and not text.endswith("\n"):
        lines = lines[:-1]
    for line in lines:
        if line.startswith("{"):
            try:
                e = json.loads(line)
            except json.JSONDecodeError:
                fail(f"not JSON: {line}")
            if kind is None or e.get("event") == kind:
                out.append(e)
    return out


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr, flush=True)
    sys.exit(1)


def skip(message):
    print(f"SKIP: {message}", flush=True)
    sys.exit(SKIP)


def check(condition, message):
    if not condition:
        fail(message)
    print(f"ok: {message}", flush=True)


_recent = collections.deque(maxlen=4)


def run(args, timeout=60, ns=None, check_rc=True):
    """Runs a command (optionally inside a namespace) and returns CompletedProcess. The command is
    echoed, but not when it is one of the last few (a poll, or polls taking turns): a failing
    test's output then shows its steps, not hundreds of the same polls."""
    cmd = (["ip", "netns", "exec", ns] if ns else []) + list(args)
    if cmd not in _recent:
        print("$ " + " ".join(cmd), flush=True)
    _recent.append(cmd)
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if check_rc and proc.returncode != 0:
        fail(f"{' '.join(cmd)} exited {proc.returncode}\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}")
    return proc


def run_json(args, **kw):
    proc = run(args, **kw)
    try:
        return json.loads(proc.stdout)
    except json.JSONDecodeError as e:
        fail(f"output of {' '.join(args)} is not JSON ({e}):\n{proc.stdout}\n{proc.stderr}")


def _end_with_parent():
    """In the child before exec: SIGTERM when the test's process ends (Linux prctl
    PR_SET_PDEATHSIG), so a test killed by ctest's timeout or by hand leaves no line running."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG = 1


class Background:
    """A process in the background, stopped with SIGTERM (then SIGKILL)."""

    def __init__(self, args, ns=None, log=None):
        cmd = (["ip", "netns", "exec", ns] if ns else []) + list(args)
        print("$ " + " ".join(cmd) + " &", flush=True)
        self.log_path = log
        self.log = open(log, "w") if log else subprocess.DEVNULL
        self.proc = subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT, preexec_fn=_end_with_parent)

    def alive(self):
        return self.proc.poll() is None

    def stop(self, timeout=10):
        if self.alive():
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.log is not subprocess.DEVNULL:
            self.log.close()
        return self.proc.returncode

    def output(self):
        if not self.log_path:
            return ""
        with open(self.log_path) as f:
            return f.read()


class VethPair:
    """Two network namespaces joined by a veth pair: our own private wire.

    Names are unique per test run and everything is deleted on exit, so
    parallel runs and crashed runs do not collide.
    """

    def __init__(self, prefix="sf"):
        if os.geteuid() != 0:
            skip("needs root for network namespaces")
        if shutil.which("ip") is None:
            skip("iproute2 (ip) is not installed")
        tag = uuid.uuid4().hex[:6]
        self.ns_a, self.ns_b = f"{prefix}a{tag}", f"{prefix}b{tag}"
        self.if_a, self.if_b = f"{prefix}va{tag}", f"{prefix}vb{tag}"

    def __enter__(self):
        for ns in (self.ns_a, self.ns_b):
            run(["ip", "netns", "add", ns])
        run(["ip", "link", "add", self.if_a, "type", "veth", "peer", "name", self.if_b])
        run(["ip", "link", "set", self.if_a, "netns", self.ns_a])
        run(["ip", "link", "set", self.if_b, "netns", self.ns_b])
        for ns, ifname in ((self.ns_a, self.if_a), (self.ns_b, self.if_b)):
            run(["ip", "link", "set", "lo", "up"], ns=ns)
            run(["ip", "link", "set", ifname, "up"], ns=ns)
        return self

    def add_pair(self, infix):
        """A second veth pair between the same namespaces (a separate wire); returns its ends."""
        tag = self.if_a[-6:]
        if_a, if_b = f"{self.if_a[:-8]}{infix}a{tag}", f"{self.if_a[:-8]}{infix}b{tag}"
        run(["ip", "link", "add", if_a, "type", "veth", "peer", "name", if_b])
        run(["ip", "link", "set", if_a, "netns", self.ns_a])
        run(["ip", "link", "set", if_b, "netns", self.ns_b])
        run(["ip", "link", "set", if_a, "up"], ns=self.ns_a)
        run(["ip", "link", "set", if_b, "up"], ns=self.ns_b)
        return if_a, if_b

    def __exit__(self, *exc):
        for ns in (self.ns_a, self.ns_b):
            subprocess.run(["ip", "netns", "del", ns], capture_output=True)
        return False


def wait_for(predicate, timeout, what, interval=0.1):
    """Polls predicate every `interval` s (a predicate that starts processes wants a long one).
    `what` may be a callable: the message then tells what was seen by the end."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(interval)
    fail(f"timed out after {timeout}s waiting for {what() if callable(what) else what}")
