// The peer of bench_web_live: the same live fan-out from Node.js with the `ws` package. Clients
// speak our live protocol (docs/web.md): {"subscribe": [...]} answered {"subscribed": [...]}; the
// server publishes {"topic": "series/<n>", "value": <number>} for every series at RATE Hz. A
// client whose socket holds more than BUFFER bytes unsent skips the message (counted as dropped):
// ws has no coalescing, and without a bound its queue grows without end.
// Usage: node live_server.mjs CLIENTS SERIES RATE SECONDS [BUFFER]
// Prints "port N" once listening, then one JSON line with the counts and the CPU time (process
// cpuUsage) of the publishing window, and exits.
import { WebSocketServer } from 'ws';

const [clients, series, rate, seconds] = process.argv.slice(2, 6).map(Number);
const bufferLimit = Number(process.argv[6] ?? 64 * 1024);
const topics = Array.from({ length: series }, (_, n) => `series/${n}`);
const subscribers = new Map(topics.map((t) => [t, new Set()]));
const counts = { published: 0, sent: 0, dropped: 0 };

const server = new WebSocketServer({ host: '127.0.0.1', port: 0, path: '/api/live', perMessageDeflate: false });
let ready = 0;
server.on('connection', (ws) => {
  const mine = new Set();
  ws.on('message', (data) => {
    const request = JSON.parse(data.toString());
    for (const t of request.subscribe ?? []) {
      if (subscribers.has(t)) {
        subscribers.get(t).add(ws);
        mine.add(t);
      }
    }
    ws.send(JSON.stringify({ subscribed: [...mine].sort() }));
    if (mine.size === series && ++ready === clients) {
      publish();
    }
  });
  ws.on('close', () => mine.forEach((t) => subscribers.get(t).delete(ws)));
  ws.on('error', () => {});
});
server.on('listening', () => console.log(`port ${server.address().port}`));

function publish() {
  const cpu = process.cpuUsage();
  const start = process.hrtime.bigint();
  let tick = 0;
  const timer = setInterval(() => {
    ++tick;
    for (let n = 0; n < series; ++n) {
      const text = JSON.stringify({ topic: topics[n], value: Math.sin((tick * series + n) * 1e-3) * 100 });
      ++counts.published;
      for (const ws of subscribers.get(topics[n])) {
        if (ws.bufferedAmount > bufferLimit) {
          ++counts.dropped;
        } else {
          ws.send(text);
          ++counts.sent;
        }
      }
    }
    if (tick >= seconds * rate) {
      clearInterval(timer);
      const used = process.cpuUsage(cpu);
      const wall = Number(process.hrtime.bigint() - start) / 1e9;
      console.log(JSON.stringify({ ...counts, cpu_s: (used.user + used.system) / 1e6, wall_s: wall }));
      for (const ws of server.clients) {
        ws.close(1001);
      }
      server.close(() => process.exit(0));
      setTimeout(() => process.exit(0), 5000);
    }
  }, 1000 / rate);
}
