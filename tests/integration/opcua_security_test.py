"""OPC UA security with node-opcua (OPC 10000-2 §4, OPC 10000-6 §6.7), both directions, on loopback:

1. node-opcua's client against `smartfactory opcua server` (default: Sign and SignAndEncrypt, a
   users file, anonymous users as viewers): its certificate is refused with
   BadSecurityChecksFailed and lands in rejected/; after `opcua pki trust` the same client
   connects with Basic256Sha256, Aes128_Sha256_RsaOaep and Aes256_Sha256_RsaPss in Sign and
   SignAndEncrypt, anonymous and with a user name; a wrong password is BadUserAccessDenied; a
   viewer cannot write or call.
2. Our command-line client against a secured node-opcua server: its certificate is untrusted
   until `opcua pki trust`, then every policy × mode works anonymously and with a user name, and
   a wrong password is BadUserAccessDenied.
3. Our client against our server from a second, untrusted installation (BadSecurityChecksFailed,
   the hint names rejected/), with a wrong password, and with users added to and removed from the
   users file while the server runs.
Values are asserted on both sides.
"""
import json
import os
import shutil
import subprocess
import tempfile

from sftest import Background, binary, check, fail, node_peer, run, wait_for_line

DEMO = "nsu=urn:smartfactory:demo;s="
POLICIES = ["Basic256Sha256", "Aes128_Sha256_RsaOaep", "Aes256_Sha256_RsaPss"]
MODES = ["Sign", "SignAndEncrypt"]


def sf(*args, check_rc=True, timeout=60):
    return run([binary(), "opcua", *args], timeout=timeout, check_rc=check_rc)


def write_file(path, text):
    with open(path, "w") as f:
        f.write(text + "\n")
    return path


def make_users(tmp):
    users = os.path.join(tmp, "users.yaml")
    sf("users", "add", users, "alice", "--role", "operator",
       "--password-file", write_file(os.path.join(tmp, "alice.pw"), "wonderland"))
    sf("users", "add", users, "victor", "--role", "viewer",
       "--password-file", write_file(os.path.join(tmp, "victor.pw"), "just-looking"))
    listed = sf("users", "list", users).stdout
    check("alice" in listed and "operator" in listed and "victor" in listed, f"users file: {listed.strip()}")
    with open(users) as f:
        text = f.read()
    check("wonderland" not in text and "$scrypt$" in text, "passwords are stored as salted scrypt hashes")
    return users


def pki_entries(pki, folder):
    listing = json.loads(sf("pki", "list", "--pki", pki, "--json").stdout)
    return [c for c in listing["certificates"] if c["folder"] == folder]


def node_client(url, pki, cases, passwords):
    args = [url, "--pki", pki]
    for user, password in passwords.items():
        args += ["--password", f"{user}={password}"]
    for case in cases:
        args += ["--case", case]
    proc = run(node_peer("opcua/node_secure_client.js") + args, timeout=300)
    results = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
    if len(results) != len(cases):
        fail(f"node-opcua client gave {len(results)} results for {len(cases)} cases:\n{proc.stdout}\n{proc.stderr}")
    return results, proc.stderr


def node_client_against_our_server(tmp, users):
    ours = os.path.join(tmp, "server-pki")
    server = Background([binary(), "opcua", "server", "--host", "127.0.0.1", "--advertised-host", "127.0.0.1",
                         "--port", "0", "--demo-model", "--status-interval", "0", "--pki", ours, "--users", users,
                         "--anonymous", "viewer"], log=os.path.join(tmp, "server.log"))
    try:
        url = wait_for_line(server, "listening on ", 30).split()[-1]
        node_pki = os.path.join(tmp, "node-client-pki")
        os.makedirs(os.path.join(node_pki, "trusted", "certs"))
        shutil.copy(os.path.join(ours, "own", "certs", "cert.der"), os.path.join(node_pki, "trusted", "certs"))
        endpoints = run(node_peer("opcua/node_secure_client.js") + [url, "--pki", node_pki, "--case",
                                                                    "Basic256Sha256:SignAndEncrypt:anonymous"],
                        timeout=120)
        first = json.loads(endpoints.stdout.splitlines()[-1])
        check(not first["ok"], f"an unknown client certificate is refused: {first.get('error')}")
        check("BadSecurityChecksFailed" in server.output() and "the client certificate was rejected" in endpoints.stderr,
              "the server answered BadSecurityChecksFailed")
        rejected = pki_entries(ours, "rejected")
        check(len(rejected) == 1 and "node-opcua" in rejected[0]["subject"],
              f"node-opcua's certificate is in rejected/: {[r['subject'] for r in rejected]}")
        sf("pki", "trust", "--pki", ours, rejected[0]["thumbprint"][:16])
        check(pki_entries(ours, "rejected") == [], "after `pki trust` nothing is left in rejected/")

        cases = [f"{p}:{m}:{u}" for p in POLICIES for m in MODES for u in ("anonymous", "alice")]
        cases += ["Basic256Sha256:SignAndEncrypt:victor", "Aes256_Sha256_RsaPss:Sign:mallory"]
        results, _ = node_client(url, node_pki, cases, {"alice": "wonderland", "victor": "just-looking",
                                                        "mallory": "wonderland"})
        for r in results[:-2]:
            what = f"node-opcua → ours {r['policy']} {r['mode']} {r['user']}"
            check(r["ok"], f"{what}: connected ({r.get('error')})")
            t = r["temperature"]
            check(t["status"] == "Good" and 10 < t["value"] < 30, f"{what}: Temperature {t}")
            if r["user"] == "alice":
                check(r["writeCounter"] == "Good" and r["counter"] == 4242, f"{what}: operator writes Counter")
                check(r["multiply"] == {"status": "Good", "outputs": [42]}, f"{what}: Multiply(6, 7)")
            else:
                check(r["writeCounter"] == "BadUserAccessDenied" and r["multiply"]["status"] == "BadUserAccessDenied",
                      f"{what}: anonymous viewers cannot write or call")
        viewer, wrong = results[-2], results[-1]
        check(viewer["ok"] and viewer["writeCounter"] == "BadUserAccessDenied"
              and viewer["multiply"]["status"] == "BadUserAccessDenied", f"viewer victor cannot write or call: {viewer}")
        check(not wrong["ok"] and "BadUserAccessDenied" in wrong["error"],
              f"an unknown user is BadUserAccessDenied: {wrong.get('error')}")
        results, _ = node_client(url, node_pki, ["Aes128_Sha256_RsaOaep:SignAndEncrypt:alice"], {"alice": "Wonderland"})
        check(not results[0]["ok"] and "BadUserAccessDenied" in results[0]["error"],
              f"a wrong password is BadUserAccessDenied: {results[0].get('error')}")
        our_client_against_our_server(tmp, url, ours, users)
    finally:
        rc = server.stop()
    check(rc == 0, "our server stops cleanly")


def our_client_against_our_server(tmp, url, server_pki, users):
    other = os.path.join(tmp, "other-installation")
    sf("pki", "init", "--pki", other)
    shutil.copy(os.path.join(server_pki, "own", "certs", "cert.der"), os.path.join(other, "trusted", "certs"))
    proc = sf("read", url, DEMO + "Demo.Temperature", "--pki", other, "--security", "Basic256Sha256:Sign",
              check_rc=False)
    check(proc.returncode != 0 and "BadSecurityChecksFailed" in proc.stderr and "rejected/" in proc.stderr,
          f"an untrusted installation is refused and told where to look: {proc.stderr.strip()[-200:]}")
    proc = sf("write", url, DEMO + "Demo.Counter", "3", "--pki", server_pki, "--user", "alice",
              "--password-file", write_file(os.path.join(tmp, "wrong.pw"), "nope"), check_rc=False)
    check(proc.returncode != 0 and "BadUserAccessDenied" in proc.stderr, "our client: a wrong password is refused")
    proc = sf("write", url, DEMO + "Demo.Counter", "3", "--pki", server_pki, "--user", "victor",
              "--password-file", os.path.join(tmp, "victor.pw"), "--json", check_rc=False)
    check(proc.returncode != 0 and "BadUserAccessDenied" in proc.stdout, "our client: a viewer cannot write")
    # The running server re-reads its users file: a user added now logs in, one removed no longer.
    sf("users", "add", users, "carol", "--role", "operator",
       "--password-file", write_file(os.path.join(tmp, "carol.pw"), "carol-pass"))
    sf("users", "remove", users, "victor")
    proc = sf("write", url, DEMO + "Demo.Counter", "5", "--pki", server_pki, "--user", "carol",
              "--password-file", os.path.join(tmp, "carol.pw"), check_rc=False)
    check(proc.returncode == 0, f"a user added while the server runs logs in and writes: {proc.stderr.strip()[-200:]}")
    proc = sf("read", url, DEMO + "Demo.Counter", "--pki", server_pki, "--user", "victor",
              "--password-file", os.path.join(tmp, "victor.pw"), check_rc=False)
    check(proc.returncode != 0 and "BadUserAccessDenied" in proc.stderr,
          f"a user removed while the server runs is refused: {proc.stderr.strip()[-200:]}")


def start_node_server(tmp, pki):
    log = open(os.path.join(tmp, "node_server.log"), "w")
    proc = subprocess.Popen(node_peer("opcua/node_server.mjs") + ["0", "--secure", pki, "--user", "alice:wonderland"],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log, text=True)
    for line in proc.stdout:
        if line.startswith("READY "):
            return proc, f"opc.tcp://127.0.0.1:{int(line.split()[1])}"
    fail("node-opcua server exited before it was ready")


def our_client_against_node_server(tmp):
    ours = os.path.join(tmp, "client-pki")
    sf("pki", "init", "--pki", ours)
    node_pki = os.path.join(tmp, "node-server-pki")
    os.makedirs(os.path.join(node_pki, "trusted", "certs"))
    shutil.copy(os.path.join(ours, "own", "certs", "cert.der"), os.path.join(node_pki, "trusted", "certs"))
    node, url = start_node_server(tmp, node_pki)
    password = write_file(os.path.join(tmp, "node-alice.pw"), "wonderland")
    try:
        proc = sf("read", url, DEMO + "Demo.Temperature", "--pki", ours, "--security", "Basic256Sha256:Sign",
                  check_rc=False)
        check(proc.returncode != 0 and "BadCertificateUntrusted" in proc.stderr,
              "our client refuses node-opcua's unknown certificate")
        rejected = pki_entries(ours, "rejected")
        check(len(rejected) == 1, f"node-opcua's certificate is in our rejected/: {rejected}")
        sf("pki", "trust", "--pki", ours, rejected[0]["thumbprint"])
        for policy in POLICIES:
            for mode in MODES:
                security = ["--pki", ours, "--security", f"{policy}:{mode}", "--json"]
                who = f"ours → node-opcua {policy} {mode}"
                t = json.loads(sf("read", url, DEMO + "Demo.Temperature", *security).stdout)[0]
                check(t["status"] == "Good" and t["type"] == "Double" and 10 < t["value"] < 30,
                      f"{who} anonymous: Temperature {t}")
                login = ["--user", "alice", "--password-file", password]
                written = json.loads(sf("write", url, DEMO + "Demo.Counter", "17", *security, *login).stdout)
                counter = json.loads(sf("read", url, DEMO + "Demo.Counter", *security, *login).stdout)[0]
                product = json.loads(sf("call", url, DEMO + "Demo", DEMO + "Demo.Multiply", "6", "7", *security,
                                        *login).stdout)
                check(written["status"] == "Good" and counter["value"] == 17 and product["outputs"] == [42],
                      f"{who} alice: write 17, read {counter['value']}, Multiply {product['outputs']}")
        proc = sf("read", url, DEMO + "Demo.Counter", "--pki", ours, "--security", "Aes256_Sha256_RsaPss:SignAndEncrypt",
                  "--user", "alice", "--password-file", write_file(os.path.join(tmp, "bad.pw"), "bad"), check_rc=False)
        check(proc.returncode != 0 and "BadUserAccessDenied" in proc.stderr,
              "node-opcua refuses a wrong password with BadUserAccessDenied")
    finally:
        node.stdin.close()
        node.wait(timeout=20)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        users = make_users(tmp)
        node_client_against_our_server(tmp, users)
        our_client_against_node_server(tmp)


main()
