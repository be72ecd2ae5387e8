// node-opcua as an operator's and a viewer's client of a machine controller's OPC UA model
// (libs/factory machine_model.hpp), for tests/integration/machine_model_test.py.
//
//   node tests/peers/opcua/machine_model_client.mjs URL --user NAME=PASSWORD [--timeout-ms T]
//
// As an anonymous viewer: browses Objects/Machines to the machine, reads its Identification,
// PackML Status.StateCurrent and every variable under Tags, calls Hold (refused). As the operator
// NAME (a UserName token on the None endpoint, its password encrypted for the server): subscribes to StateCurrent and calls
// Reset, Start, Hold, Unhold and Unhold again, waiting after each accepted call for the state it
// leads to. Prints one JSON document on stdout; steps that fail are listed in "errors".
import "./quiet_console.mjs";
import process from "node:process";

import {
  AttributeIds,
  ClientMonitoredItem,
  ClientSubscription,
  DataType,
  MessageSecurityMode,
  OPCUAClient,
  SecurityPolicy,
  TimestampsToReturn,
  UserTokenType,
} from "node-opcua";

import { children, resolve } from "./browse_util.mjs";

function parseArgs(argv) {
  const args = { url: argv[2], user: "", password: "", timeoutMs: 20000 };
  for (let i = 3; i < argv.length; i += 2) {
    if (argv[i] === "--user") {
      const at = argv[i + 1].indexOf("=");
      args.user = argv[i + 1].slice(0, at);
      args.password = argv[i + 1].slice(at + 1);
    } else if (argv[i] === "--timeout-ms") args.timeoutMs = Number(argv[i + 1]);
    else throw new Error(`unknown option ${argv[i]}`);
  }
  if (!args.url || !args.user) throw new Error("usage: machine_model_client.mjs URL --user NAME=PASSWORD");
  return args;
}

async function value(session, nodeId) {
  const dv = await session.read({ nodeId, attributeId: AttributeIds.Value });
  const v = dv.value.value;
  return { value: v && typeof v === "object" && "text" in v ? v.text : v, status: dv.statusCode.name };
}

function connectOptions() {
  return {
    applicationName: "node-opcua machine model peer",
    endpointMustExist: false,
    securityMode: MessageSecurityMode.None,
    securityPolicy: SecurityPolicy.None,
    connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
    requestedSessionTimeout: 30000,
  };
}

// Every variable of the machine's Tags folder: its value's DataType and its StatusCode.
async function readTags(session, machine) {
  const tags = {};
  for (const r of await children(session, await resolve(session, machine, "Tags"))) {
    const dv = await session.read({ nodeId: r.nodeId, attributeId: AttributeIds.Value });
    tags[r.browseName.name] = { type: DataType[dv.value.dataType], status: dv.statusCode.name };
  }
  return tags;
}

// The viewer's part: browse, read, a refused call. Returns what the operator needs.
async function asViewer(args, out) {
  const client = OPCUAClient.create(connectOptions());
  await client.connect(args.url);
  const session = await client.createSession();
  try {
    out.namespaces = (await session.read({ nodeId: "ns=0;i=2255", attributeId: AttributeIds.Value })).value.value;
    const machines = await resolve(session, "ns=0;i=85", "Machines");
    const found = await children(session, machines);
    out.machines = found.map((r) => ({ name: r.browseName.name, namespace: out.namespaces[r.browseName.namespaceIndex] }));
    const machine = found[0].nodeId.toString();
    out.machineChildren = (await children(session, machine)).map((r) => r.browseName.name).sort();
    out.identification = {};
    for (const name of ["Manufacturer", "Model", "SerialNumber", "DeviceClass"]) {
      out.identification[name] = (await value(session, await resolve(session, machine, `Identification/${name}`))).value;
    }
    out.tags = await readTags(session, machine);
    const ids = {
      machine,
      state: await resolve(session, machine, "PackML/Status/StateCurrent"),
      execute: await resolve(session, machine, "PackML/BaseStateMachine/MachineState/ExecuteState"),
    };
    ids.hold = await resolve(session, ids.execute, "Hold");
    out.stateBefore = (await value(session, ids.state)).value;
    out.viewerHold = (await session.call({ objectId: ids.execute, methodId: ids.hold, inputArguments: [] })).statusCode.name;
    return ids;
  } finally {
    await session.close();
    await client.disconnect();
  }
}

// Resolves when the subscription delivered `state` last (or rejects after timeoutMs).
function waiter(states, timeoutMs) {
  const pending = [];
  const check = () => {
    for (const p of [...pending]) {
      if (states.at(-1) === p.state) {
        clearTimeout(p.timer);
        pending.splice(pending.indexOf(p), 1);
        p.resolve();
      }
    }
  };
  const until = (state) =>
    new Promise((resolve, reject) => {
      const p = { state, resolve };
      p.timer = setTimeout(() => reject(new Error(`state ${state} not seen (saw ${states.join(",")})`)), timeoutMs);
      pending.push(p);
      check();
    });
  return { check, until };
}

async function asOperator(args, ids, out) {
  const client = OPCUAClient.create(connectOptions());
  await client.connect(args.url);
  const session = await client.createSession({ type: UserTokenType.UserName, userName: args.user, password: args.password });
  try {
    const sub = ClientSubscription.create(session, {
      requestedPublishingInterval: 50,
      requestedLifetimeCount: 600,
      requestedMaxKeepAliveCount: 10,
      maxNotificationsPerPublish: 100,
      publishingEnabled: true,
      priority: 1,
    });
    out.states = [];
    const wait = waiter(out.states, args.timeoutMs);
    const item = ClientMonitoredItem.create(
      sub,
      { nodeId: ids.state, attributeId: AttributeIds.Value },
      { samplingInterval: 0, discardOldest: true, queueSize: 20 },
      TimestampsToReturn.Both,
    );
    item.on("changed", (dv) => {
      out.states.push(dv.value.value);
      wait.check();
    });
    await wait.until(out.stateBefore);
    out.calls = [];
    const method = async (name) => {
      const methodId = await resolve(session, ids.execute, name);
      const status = (await session.call({ objectId: ids.execute, methodId, inputArguments: [] })).statusCode.name;
      out.calls.push({ method: name, status });
      return status;
    };
    // Each accepted command and the state the controller reaches through it (OPC 30050 numbers).
    for (const [name, state] of [["Reset", 4], ["Start", 6], ["Hold", 11], ["Unhold", 6]]) {
      if ((await method(name)) === "Good") await wait.until(state);
    }
    await method("Unhold");  // in Execute: nothing to unhold
    await sub.terminate();
  } finally {
    await session.close();
    await client.disconnect();
  }
}

(async () => {
  const args = parseArgs(process.argv);
  const out = { errors: [] };
  let ids = null;
  try {
    ids = await asViewer(args, out);
  } catch (err) {
    out.errors.push(`viewer: ${err.message}`);
  }
  if (ids) {
    try {
      await asOperator(args, ids, out);
    } catch (err) {
      out.errors.push(`operator: ${err.message}`);
    }
  }
  process.stdout.write(`${JSON.stringify(out)}\n`);
  process.exit(0);
})().catch((err) => {
  console.error(err.stack || String(err));
  process.exit(1);
});
