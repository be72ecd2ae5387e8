"""`smartfactory cloud --tls-cert --tls-key`: the dashboard over HTTPS only (docs/dashboard.md, TLS).

1. A certificate made by the `openssl` CLI as docs/dashboard.md shows; the cloud prints an https://
   URL; Python's TLS client (ssl, the certificate as its only trust anchor) gets the catalog with
   Strict-Transport-Security and logs in with a Secure session cookie.
2. Plain HTTP on that port gets no HTTP answer.
3. A key that is not the certificate's stops the cloud at its start with a message naming it.
"""
import http.client
import json
import os
import shutil
import ssl
import subprocess
import tempfile

from sftest import Background, binary, check, run, skip, wait_for_line


def make_certificate(tmp, name):
    chain, key = os.path.join(tmp, f"{name}-chain.pem"), os.path.join(tmp, f"{name}-key.pem")
    run(["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes", "-days", "1",
         "-subj", "/CN=localhost", "-addext", "subjectAltName=DNS:localhost,IP:127.0.0.1",
         "-keyout", key, "-out", chain])
    return chain, key


def write_users(tmp):
    password = os.path.join(tmp, "password")
    with open(password, "w") as f:
        f.write("secret\n")
    users = os.path.join(tmp, "users.yaml")
    run([binary(), "opcua", "users", "add", users, "olga", "--role", "operator", "--password-file", password])
    return users


def write_config(tmp):
    path = os.path.join(tmp, "cloud.yaml")
    with open(path, "w") as f:
        f.write(f"historian:\n  url: sqlite:{tmp}/history.db\n  buffer: {tmp}/buffer\n"
                "servers:\n  - name: away\n    url: opc.tcp://127.0.0.1:1\n"
                "    subscribe:\n      - browse_path: /Objects\n")
    return path


def cloud(config, users, chain, key, log):
    return Background([binary(), "cloud", "--config", config, "--status-interval", "0", "--http", "0",
                       "--web-users", users, "--tls-cert", chain, "--tls-key", key], log=log)


def https(port, ca, method, path, body=None):
    context = ssl.create_default_context(cafile=ca)
    connection = http.client.HTTPSConnection("127.0.0.1", port, context=context, timeout=30)
    headers = {"Content-Type": "application/json"} if body is not None else {}
    connection.request(method, path, body=body, headers=headers)
    response = connection.getresponse()
    return response.status, response.headers, response.read()


def plain_http_answer(port):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    try:
        connection.request("GET", "/api/catalog")
        return connection.getresponse().status
    except (http.client.HTTPException, OSError):
        return None


def main():
    if shutil.which("openssl") is None:
        skip("the openssl CLI is not installed (scripts/setup installs it)")
    with tempfile.TemporaryDirectory() as tmp:
        chain, key = make_certificate(tmp, "server")
        _, other_key = make_certificate(tmp, "other")
        users, config = write_users(tmp), write_config(tmp)

        server = cloud(config, users, chain, key, os.path.join(tmp, "cloud.log"))
        try:
            url = wait_for_line(server, "dashboard on ", 60).split()[-1]
            check(url.startswith("https://127.0.0.1:"), f"the printed URL is https: {url}")
            port = int(url.rstrip("/").rsplit(":", 1)[1])

            status, headers, body = https(port, chain, "GET", "/api/catalog")
            check(status == 200 and "box_types" in json.loads(body), f"the catalog over HTTPS: {status} {body[:200]}")
            check(headers["Strict-Transport-Security"] == "max-age=31536000",
                  f"Strict-Transport-Security: {headers['Strict-Transport-Security']}")
            status, headers, body = https(port, chain, "POST", "/api/session",
                                          json.dumps({"user": "olga", "password": "secret"}))
            cookie = headers["Set-Cookie"] or ""
            check(status == 200 and "; Secure" in cookie, f"a Secure session cookie: {status} {cookie}")

            check(plain_http_answer(port) is None, "plain HTTP on the TLS port gets no HTTP answer")
            status, _, _ = https(port, chain, "GET", "/api/catalog")
            check(status == 200, "the server serves on after the plain request")
        finally:
            rc = server.stop()
        check(rc == 0, "the cloud stops cleanly on SIGTERM")

        proc = subprocess.run([binary(), "cloud", "--config", config, "--status-interval", "0", "--http", "0",
                               "--web-users", users, "--tls-cert", chain, "--tls-key", other_key, "--duration", "30"],
                              capture_output=True, text=True, timeout=120)
        check(proc.returncode == 1 and f"{other_key}: does not match the certificate" in proc.stderr,
              f"a key that is not the certificate's stops the cloud: rc {proc.returncode}: {proc.stderr.strip()}")


main()
