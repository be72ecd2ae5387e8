// node-opcua as the client peer of our OPC UA server: runs the demo-model scenario
// against URL and prints one JSON object with everything it saw, which
// tests/integration/opcua_interop_test.py asserts.
//
//   node tests/peers/opcua/node_client.js opc.tcp://127.0.0.1:4840 [--samples N]
//
// The scenario: GetEndpoints, browse Objects and Demo, read Temperature and ServerStatus, write
// Counter and read it back, call Multiply(6, 7), subscribe to Temperature until N data changes
// arrived, read an unknown node. Failures of single steps are reported in the JSON ("errors"),
// a failure to connect exits with status 2.
"use strict";

const { withTimeout } = require("./peer_util.js");

const DEMO_URI = "urn:smartfactory:demo";

function parseArgs(argv) {
  const args = { url: argv[2], samples: 3, timeoutMs: 20000 };
  for (let i = 3; i < argv.length; i += 2) {
    if (argv[i] === "--samples") args.samples = Number(argv[i + 1]);
    else if (argv[i] === "--timeout-ms") args.timeoutMs = Number(argv[i + 1]);
    else throw new Error(`unknown option ${argv[i]}`);
  }
  if (!args.url) throw new Error("usage: node_client.js URL [--samples N] [--timeout-ms T]");
  return args;
}

async function step(out, name, fn) {
  try {
    out[name] = await fn();
  } catch (err) {
    out.errors.push(`${name}: ${err.message}`);
  }
}

async function subscribeSamples(ua, session, nodeId, count, timeoutMs) {
  const sub = ua.ClientSubscription.create(session, {
    requestedPublishingInterval: 100,
    requestedLifetimeCount: 600,
    requestedMaxKeepAliveCount: 10,
    maxNotificationsPerPublish: 100,
    publishingEnabled: true,
    priority: 1,
  });
  const values = [];
  const done = new Promise((resolve) => {
    const item = ua.ClientMonitoredItem.create(
      sub,
      { nodeId, attributeId: ua.AttributeIds.Value },
      { samplingInterval: 100, discardOldest: true, queueSize: 10 },
      ua.TimestampsToReturn.Both
    );
    item.on("changed", (dv) => {
      values.push({ value: dv.value.value, status: dv.statusCode.name });
      if (values.length >= count) resolve();
    });
  });
  await withTimeout(done, timeoutMs, "subscription");
  await sub.terminate();
  return values;
}

async function run(ua, args) {
  const out = { errors: [] };
  const client = ua.OPCUAClient.create({
    applicationName: "node-opcua interop peer",
    endpointMustExist: false,
    securityMode: ua.MessageSecurityMode.None,
    securityPolicy: ua.SecurityPolicy.None,
    connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
    requestedSessionTimeout: 30000,
  });
  try {
    await withTimeout(client.connect(args.url), args.timeoutMs, "connect");
  } catch (err) {
    console.error(`connect failed: ${err.message}`);
    process.exit(2);
  }
  await step(out, "endpoints", async () =>
    (await client.getEndpoints()).map((e) => ({
      url: e.endpointUrl,
      policy: e.securityPolicyUri,
      mode: ua.MessageSecurityMode[e.securityMode],
    }))
  );
  const session = await withTimeout(client.createSession(), args.timeoutMs, "createSession");
  await step(out, "namespaces", async () => {
    const dv = await session.read({ nodeId: "ns=0;i=2255", attributeId: ua.AttributeIds.Value });
    return dv.value.value;
  });
  const ns = (out.namespaces || []).indexOf(DEMO_URI);
  const id = (name) => `ns=${ns};s=${name}`;
  await step(out, "objects", async () =>
    (await session.browse("ns=0;i=85")).references.map((r) => r.browseName.name)
  );
  await step(out, "demo", async () =>
    (await session.browse(id("Demo"))).references.map((r) => r.browseName.name)
  );
  await step(out, "state", async () => {
    const dv = await session.read({ nodeId: "ns=0;i=2259", attributeId: ua.AttributeIds.Value });
    return dv.value.value;
  });
  await step(out, "temperature", async () => {
    const dv = await session.read({ nodeId: id("Demo.Temperature"), attributeId: ua.AttributeIds.Value });
    return { value: dv.value.value, type: ua.DataType[dv.value.dataType], status: dv.statusCode.name };
  });
  await step(out, "write_temperature", async () => {
    const st = await session.write({
      nodeId: id("Demo.Temperature"),
      attributeId: ua.AttributeIds.Value,
      value: { value: { dataType: ua.DataType.Double, value: 1.5 } },
    });
    return st.name;
  });
  await step(out, "write_counter", async () => {
    const st = await session.write({
      nodeId: id("Demo.Counter"),
      attributeId: ua.AttributeIds.Value,
      value: { value: { dataType: ua.DataType.Int32, value: 4242 } },
    });
    return st.name;
  });
  await step(out, "counter", async () => {
    const dv = await session.read({ nodeId: id("Demo.Counter"), attributeId: ua.AttributeIds.Value });
    return dv.value.value;
  });
  await step(out, "multiply", async () => {
    const res = await session.call({
      objectId: id("Demo"),
      methodId: id("Demo.Multiply"),
      inputArguments: [
        { dataType: ua.DataType.Double, value: 6 },
        { dataType: ua.DataType.Double, value: 7 },
      ],
    });
    return { status: res.statusCode.name, outputs: res.outputArguments.map((v) => v.value) };
  });
  await step(out, "unknown", async () => {
    const dv = await session.read({ nodeId: `ns=${ns};s=NoSuchNode`, attributeId: ua.AttributeIds.Value });
    return dv.statusCode.name;
  });
  await step(out, "samples", () =>
    subscribeSamples(ua, session, id("Demo.Temperature"), args.samples, args.timeoutMs)
  );
  await session.close();
  await client.disconnect();
  return out;
}

(async () => {
  const args = parseArgs(process.argv);
  const ua = await import("node-opcua");
  const out = await run(ua, args);
  process.stdout.write(`${JSON.stringify(out)}\n`);
  process.exit(0);
})().catch((err) => {
  console.error(err.stack || String(err));
  process.exit(1);
});
