// Node.js's TLS stack (its own OpenSSL build, node:https) and the `ws` package as the peers of
// libs/web's HTTPS and WSS tests (libs/web/test/tls_test.cpp). The server's certificate is
// verified against the CA file given, as a browser would (rejectUnauthorized, the IP in
// subjectAltName).
//
//   node tests/peers/web/tls_client.mjs https PORT CA_PEM PATH [TLS_OPTIONS_JSON]
//     TLS_OPTIONS_JSON: more options of tls.connect, e.g. {"maxVersion": "TLSv1.2", "ciphers": ...};
//     one JSON line: {"status", "headers", "body", "protocol", "cipher"} or {"error", "message"}
//   node tests/peers/web/tls_client.mjs wss PORT CA_PEM TOPIC
//     subscribes to TOPIC, prints every message received as one line, ends when stdin closes;
//     {"error", "message"} if the connection fails
import fs from "node:fs";
import https from "node:https";
import process from "node:process";

import WebSocket from "ws";

const [mode, port, caFile, arg, tlsOptions] = process.argv.slice(2);
const ca = fs.readFileSync(caFile);

function print(value) {
  process.stdout.write(JSON.stringify(value) + "\n");
}

function failed(error) {
  print({ error: error.code ?? "", message: error.message });
  process.exit(0);
}

function get(path) {
  const options = { host: "127.0.0.1", port: Number(port), path, ca, agent: false, ...JSON.parse(tlsOptions ?? "{}") };
  const request = https.get(options, (response) => {
    const protocol = response.socket.getProtocol();
    const cipher = response.socket.getCipher().standardName;
    let body = "";
    response.setEncoding("utf8");
    response.on("data", (chunk) => (body += chunk));
    response.on("end", () => {
      print({
        status: response.statusCode,
        headers: response.headers,
        body,
        protocol,
        cipher,
      });
      process.exit(0);
    });
  });
  request.on("error", failed);
}

function live(topic) {
  const ws = new WebSocket(`wss://127.0.0.1:${port}/api/live`, { ca });
  ws.on("open", () => ws.send(JSON.stringify({ subscribe: [topic] })));
  ws.on("message", (data) => process.stdout.write(data.toString() + "\n"));
  ws.on("error", failed);
  process.stdin.on("end", () => ws.close(1000));
  process.stdin.resume();
  ws.on("close", (code) => {
    print({ closed: code });
    process.exit(0);
  });
}

if (mode === "https") {
  get(arg);
} else if (mode === "wss") {
  live(arg);
} else {
  console.error(`unknown mode ${mode}`);
  process.exit(2);
}
