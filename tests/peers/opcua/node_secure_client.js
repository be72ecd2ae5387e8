// node-opcua as a secured client (OPC 10000-2 §4): for each case POLICY:MODE:USER it connects to URL with
// that security policy and mode, logs in (anonymous, or USER with its password from --password
// USER=PASS) and reads, writes and calls on the demo model; prints one JSON line per case, which
// tests/integration/opcua_security_test.py and bench/bench_opcua_security assert or time.
//
//   node tests/peers/opcua/node_secure_client.js URL --pki DIR [--password alice=wonderland]...
//        [--case Basic256Sha256:SignAndEncrypt:anonymous]... [--timeout-ms T]
//        [--reads N]                     per case, N reads of Demo.Temperature (for the benchmark)
//
// DIR is node-opcua's PKI folder of the client (own/certs/client_certificate.pem is made on
// first use; the server's certificate must be in trusted/certs: unknown servers are refused).
// Each result: {policy, mode, user, ok, error, connectMs, temperature, writeCounter, counter,
// multiply, readsPerSecond}.
"use strict";

const { withTimeout } = require("./peer_util.js");

const fs = require("node:fs");
const path = require("node:path");

const DEMO_URI = "urn:smartfactory:demo";

function parseArgs(argv) {
  const args = { url: argv[2], pki: "", passwords: {}, cases: [], timeoutMs: 20000, reads: 0 };
  for (let i = 3; i < argv.length; i += 2) {
    const value = argv[i + 1];
    if (argv[i] === "--pki") args.pki = value;
    else if (argv[i] === "--password") {
      const at = value.indexOf("=");
      args.passwords[value.slice(0, at)] = value.slice(at + 1);
    } else if (argv[i] === "--case") args.cases.push(value);
    else if (argv[i] === "--timeout-ms") args.timeoutMs = Number(value);
    else if (argv[i] === "--reads") args.reads = Number(value);
    else throw new Error(`unknown option ${argv[i]}`);
  }
  if (!args.url || !args.pki || args.cases.length === 0) {
    throw new Error("usage: node_secure_client.js URL --pki DIR --case POLICY:MODE:USER...");
  }
  return args;
}

async function exercise(ua, session, out, reads) {
  const namespaces = (await session.read({ nodeId: "ns=0;i=2255", attributeId: ua.AttributeIds.Value })).value.value;
  const id = (name) => `ns=${namespaces.indexOf(DEMO_URI)};s=${name}`;
  const temperature = await session.read({ nodeId: id("Demo.Temperature"), attributeId: ua.AttributeIds.Value });
  out.temperature = { value: temperature.value.value, status: temperature.statusCode.name };
  const written = await session.write({
    nodeId: id("Demo.Counter"),
    attributeId: ua.AttributeIds.Value,
    value: { value: { dataType: ua.DataType.Int32, value: 4242 } },
  });
  out.writeCounter = written.name;
  out.counter = (await session.read({ nodeId: id("Demo.Counter"), attributeId: ua.AttributeIds.Value })).value.value;
  const called = await session.call({
    objectId: id("Demo"),
    methodId: id("Demo.Multiply"),
    inputArguments: [
      { dataType: ua.DataType.Double, value: 6 },
      { dataType: ua.DataType.Double, value: 7 },
    ],
  });
  out.multiply = { status: called.statusCode.name, outputs: called.outputArguments.map((v) => v.value) };
  if (reads > 0) {
    const start = process.hrtime.bigint();
    for (let i = 0; i < reads; i += 1) {
      await session.read({ nodeId: id("Demo.Temperature"), attributeId: ua.AttributeIds.Value });
    }
    out.readsPerSecond = reads / (Number(process.hrtime.bigint() - start) / 1e9);
  }
}

async function runCase(ua, args, spec, certificateManager) {
  const [policy, mode, user] = spec.split(":");
  const out = { policy, mode, user, ok: false };
  const client = ua.OPCUAClient.create({
    applicationName: "node-opcua security peer",
    endpointMustExist: false,
    securityPolicy: ua.SecurityPolicy[policy],
    securityMode: ua.MessageSecurityMode[mode],
    clientCertificateManager: certificateManager,
    connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
    requestedSessionTimeout: 30000,
  });
  try {
    const start = process.hrtime.bigint();
    await withTimeout(client.connect(args.url), args.timeoutMs, "connect");
    const identity =
      user === "anonymous"
        ? { type: ua.UserTokenType.Anonymous }
        : { type: ua.UserTokenType.UserName, userName: user, password: args.passwords[user] ?? "" };
    const session = await withTimeout(client.createSession(identity), args.timeoutMs, "createSession");
    out.connectMs = Number(process.hrtime.bigint() - start) / 1e6;
    try {
      await exercise(ua, session, out, args.reads);
      out.ok = true;
    } finally {
      await session.close();
    }
  } catch (err) {
    out.error = err.message;
  } finally {
    await client.disconnect().catch(() => {});
  }
  return out;
}

(async () => {
  const args = parseArgs(process.argv);
  // node-opcua prints warnings with console.log; stdout is for the results only.
  console.log = (...a) => console.error(...a);
  console.warn = (...a) => console.error(...a);
  const ua = await import("node-opcua");
  fs.mkdirSync(path.join(args.pki, "trusted", "certs"), { recursive: true });
  const certificateManager = new ua.OPCUACertificateManager({
    rootFolder: args.pki,
    automaticallyAcceptUnknownCertificate: false,
  });
  await certificateManager.initialize();
  for (const spec of args.cases) {
    process.stdout.write(`${JSON.stringify(await runCase(ua, args, spec, certificateManager))}\n`);
  }
  await certificateManager.dispose();
  process.exit(0);
})().catch((err) => {
  console.error(err.stack || String(err));
  process.exit(1);
});
