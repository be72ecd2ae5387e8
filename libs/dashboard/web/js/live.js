// The live stream: one WebSocket on /api/live (same origin, the session cookie goes with the
// upgrade). Topics are subscribed with {"subscribe": [...]}, updates arrive as
// {"topic": "...", "value": ...}; replies {"subscribed": [...]} and {"error": ...} come between.
// A lost connection is opened again after a growing pause (0.5 s doubling up to 30 s, with
// jitter so a restarted server is not hit by every browser at once) and every topic is
// subscribed again; listeners of `open` refetch what they may have missed meanwhile.

const FIRST_DELAY_MS = 500;
const MAX_DELAY_MS = 30000;

export class Live {
  constructor(path = '/api/live') {
    this.path = path;
    this.handlers = new Map();  // topic → Set of functions(value, topic)
    this.listeners = {open: new Set(), close: new Set(), error: new Set()};
    this.socket = null;
    this.attempt = 0;
    this.timer = null;
    this.stopped = true;
    this.connected = false;
  }

  url() {
    const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
    return `${scheme}//${location.host}${this.path}`;
  }

  // Listens to `open` (connected, topics sent again), `close` (lost) or `error` (the server's
  // error replies: a refused topic, a malformed request).
  on(event, fn) {
    this.listeners[event].add(fn);
    return () => this.listeners[event].delete(fn);
  }

  emit(event, arg) {
    for (const fn of this.listeners[event]) fn(arg);
  }

  start() {
    if (!this.stopped) return;
    this.stopped = false;
    this.connect();
  }

  stop() {
    this.stopped = true;
    clearTimeout(this.timer);
    if (this.socket) this.socket.close(1000, 'page done');
    this.socket = null;
  }

  // Calls fn(value, topic) for every update of the topic; returns the function that unsubscribes.
  subscribe(topic, fn) {
    let set = this.handlers.get(topic);
    if (!set) {
      set = new Set();
      this.handlers.set(topic, set);
      this.send({subscribe: [topic]});
    }
    set.add(fn);
    return () => {
      set.delete(fn);
      if (set.size === 0 && this.handlers.get(topic) === set) {
        this.handlers.delete(topic);
        this.send({unsubscribe: [topic]});
      }
    };
  }

  send(message) {
    if (this.socket && this.socket.readyState === WebSocket.OPEN) this.socket.send(JSON.stringify(message));
  }

  connect() {
    const socket = new WebSocket(this.url());
    this.socket = socket;
    socket.addEventListener('open', () => {
      this.attempt = 0;
      this.connected = true;
      if (this.handlers.size) this.send({subscribe: [...this.handlers.keys()]});
      this.emit('open');
    });
    socket.addEventListener('message', (event) => this.receive(event.data));
    socket.addEventListener('close', () => {
      if (this.socket !== socket) return;
      const was = this.connected;
      this.connected = false;
      this.socket = null;
      if (was) this.emit('close');
      if (!this.stopped) this.retry();
    });
  }

  retry() {
    const base = Math.min(MAX_DELAY_MS, FIRST_DELAY_MS * 2 ** this.attempt);
    this.attempt += 1;
    const delay = base / 2 + Math.random() * (base / 2);
    this.timer = setTimeout(() => this.connect(), delay);
  }

  receive(text) {
    let message;
    try {
      message = JSON.parse(text);
    } catch {
      this.emit('error', {error: 'an update that is not JSON'});
      return;
    }
    if (message && typeof message.topic === 'string') {
      for (const fn of this.handlers.get(message.topic) || []) fn(message.value, message.topic);
    } else if (message && message.error) {
      this.emit('error', message);
    }
  }
}
