// The browser's half of bench_dashboard (bench/dashboard/README in docs/performance.md): headless
// Chromium (tests/browser/browser.mjs launches it) against the dashboard of a running line.
//   1. Page weight and time to first live value: the operator page loaded LOADS times and the
//      consumer page once, each in a fresh tab with the cache disabled, logged in; the bytes come
//      from Chromium's network events (Network.loadingFinished encodedDataLength: headers and body
//      as received), times from the page's clock (performance.now(), 0 = navigation start).
//   2. End to end: on the last operator page, with the smart robot's detail open, the page's own
//      live stream subscribes TOPICS (series/<id> of its axis positions) until SAMPLES updates came
//      or SECONDS passed (the robot stands still between jobs and while its line recovers); each
//      update is stamped when its message event reaches the page's scripts, in wall-clock time as
//      the page knows it (performance.timeOrigin + performance.now()). A plain WebSocket client
//      (Node's ws, the page's session cookie) subscribes the same topics at the same time: the
//      dashboard's path without the browser.
// Prints `note:` lines while it runs and one {"result": {...}} line at the end (bench_dashboard
// reads it).
import WebSocket from 'ws';
import {WAIT_MS, fail, launch, login, note, options} from '../../tests/browser/browser.mjs';

const opts = options({
  machine: {type: 'string'},
  topics: {type: 'string'},
  samples: {type: 'string', default: '1000'},
  seconds: {type: 'string', default: '300'},
  loads: {type: 'string', default: '3'},
});
const topics = (opts.topics || '').split(',').filter(Boolean);
if (!opts.machine || topics.length === 0) fail('--machine and --topics are required');

// Runs in every page before its own scripts (not subject to its CSP): every WebSocket the page
// opens gets a first message listener, so the stamp is taken before the page's handlers run.
function hooks() {
  const bench = {sockets: [], topics: new Set(), samples: [], wsOpen: null, firstLive: null, firstLiveFrame: null};
  window.sfBench = bench;
  const Native = window.WebSocket;
  window.WebSocket = class extends Native {
    constructor(...args) {
      super(...args);
      bench.sockets.push(this);
      this.addEventListener('open', () => {
        if (bench.wsOpen === null) bench.wsOpen = performance.now();
        if (bench.topics.size) this.send(JSON.stringify({subscribe: [...bench.topics]}));
      });
      this.addEventListener('message', (event) => {
        const now = performance.now();
        if (typeof event.data !== 'string') return;
        let message;
        try { message = JSON.parse(event.data); } catch { return; }
        if (!message || typeof message.topic !== 'string') return;
        if (bench.firstLive === null) {
          bench.firstLive = now;
          // The frame that paints what the page's handler (which runs next) changed.
          requestAnimationFrame(() => { bench.firstLiveFrame = performance.now(); });
        }
        if (bench.topics.has(message.topic) && message.value) {
          bench.samples.push([message.topic.slice('series/'.length), message.value.t, performance.timeOrigin + now]);
        }
      });
    }
  };
}

// Loads `path` in a new tab of `context` with the cache disabled: every request with its bytes.
async function load(context, path, waitLive) {
  const page = await context.newPage();
  await page.setViewport({width: 1280, height: 900});
  page.setDefaultTimeout(WAIT_MS);
  await page.setCacheEnabled(false);
  await page.evaluateOnNewDocument(hooks);
  const cdp = await page.createCDPSession();
  await cdp.send('Network.enable');
  const requests = new Map();
  cdp.on('Network.requestWillBeSent', (e) => requests.set(e.requestId, {url: e.request.url, type: e.type, bytes: 0}));
  cdp.on('Network.loadingFinished', (e) => {
    const r = requests.get(e.requestId);
    if (r) r.bytes = e.encodedDataLength;
  });
  cdp.on('Network.loadingFailed', (e) => {
    const r = requests.get(e.requestId);
    if (r) r.failed = e.errorText;
  });
  await page.goto(new URL(path, opts.url).href, {waitUntil: 'load'});
  if (waitLive) await page.waitForFunction(() => window.sfBench.firstLiveFrame !== null);
  await page.waitForNetworkIdle({idleTime: 1000});
  const times = await page.evaluate(() => {
    const nav = performance.getEntriesByType('navigation')[0];
    const b = window.sfBench;
    return {dom_content_loaded_ms: nav.domContentLoadedEventEnd, load_ms: nav.loadEventEnd, ws_open_ms: b.wsOpen,
      first_live_ms: b.firstLive, first_live_frame_ms: b.firstLiveFrame};
  });
  await cdp.detach();
  const list = [...requests.values()].map((r) => ({path: new URL(r.url).pathname, type: r.type, bytes: r.bytes,
    failed: r.failed || ''}));
  note(`${path}: ${list.length} requests, ${list.reduce((s, r) => s + r.bytes, 0)} bytes`);
  return {page, figures: {path, requests: list, ...times}};
}

// A WebSocket client outside the browser on the same live stream and topics, with the context's
// session cookie; its samples stamped as the page's are (this process's performance clock).
async function plainClient(context) {
  const cookie = (await context.cookies()).map((c) => `${c.name}=${c.value}`).join('; ');
  const url = new URL('api/live', opts.url);
  url.protocol = 'ws:';
  const socket = new WebSocket(url.href, {headers: {Cookie: cookie}, perMessageDeflate: false});
  const samples = [];
  const wanted = new Set(topics);
  socket.on('message', (data) => {
    const at = performance.timeOrigin + performance.now();
    const message = JSON.parse(data.toString());
    if (wanted.has(message.topic) && message.value) samples.push([message.topic.slice('series/'.length), message.value.t, at]);
  });
  await new Promise((resolve, reject) => {
    socket.once('open', resolve);
    socket.once('error', reject);
  });
  socket.send(JSON.stringify({subscribe: topics}));
  return {samples, close: () => socket.close()};
}

// The page's own socket (and the plain client) subscribe the topics until enough samples came or
// time is up; the samples stamped and the window (wall-clock ms) they were followed in.
async function follow(context, page) {
  await page.click(`#machines button[data-select="${opts.machine}"]`);
  await page.waitForSelector('#machine:not([hidden])');
  const client = await plainClient(context);
  const from = Date.now();
  await page.evaluate((list) => {
    const b = window.sfBench;
    list.forEach((t) => b.topics.add(t));
    for (const s of b.sockets) if (s.readyState === WebSocket.OPEN) s.send(JSON.stringify({subscribe: list}));
  }, topics);
  note(`following ${topics.length} series of ${opts.machine}: ${opts.samples} samples, at most ${opts.seconds} s`);
  const until = from + Number(opts.seconds) * 1000;
  let count = 0;
  while (Date.now() < until && count < Number(opts.samples)) {
    await new Promise((resolve) => setTimeout(resolve, 1000));
    const now = await page.evaluate(() => window.sfBench.samples.length);
    if (Math.floor(now / 100) > Math.floor(count / 100)) note(`${now} samples at the page`);
    count = now;
  }
  client.close();
  const live = await page.evaluate((windowFrom) => ({
    samples: window.sfBench.samples,
    window_ms: [windowFrom, Date.now()],
    // The page's wall clock against the system's, read at once: what the stamps may be off by.
    clock_offset_ms: performance.timeOrigin + performance.now() - Date.now(),
  }), from);
  return {...live, client_samples: client.samples};
}

async function main() {
  const browser = await launch(opts);
  try {
    const context = await browser.createBrowserContext();
    const first = await context.newPage();
    await first.goto(new URL('operator.html', opts.url).href, {waitUntil: 'load'});
    await login(first, opts.user, opts.password);
    await first.close();
    const consumer = await load(context, 'index.html', false);
    await consumer.page.close();
    const loads = [];
    let page = null;
    for (let i = 0; i < Number(opts.loads); ++i) {
      if (page) await page.close();
      const loaded = await load(context, 'operator.html', true);
      page = loaded.page;
      loads.push(loaded.figures);
    }
    await page.bringToFront();
    const live = await follow(context, page);
    const parsed = (list) => list.map(([id, t, at]) => [id, Date.parse(t), at]);
    note(`${live.samples.length} samples at the page, ${live.client_samples.length} at the plain client; ` +
      `page clock − system clock ${live.clock_offset_ms.toFixed(3)} ms`);
    console.log(JSON.stringify({result: {chromium: await browser.version(), operator: loads,
      consumer: consumer.figures, samples: parsed(live.samples), client_samples: parsed(live.client_samples),
      window_ms: live.window_ms, clock_offset_ms: live.clock_offset_ms}}));
  } finally {
    await browser.close();
  }
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
