// The line as a schematic drawn from /api/layout (the layout file's belts with their paths and
// stations, the robots at their bases, the box uploader and downloader at their stations), each
// machine and conveyor coloured by its PackML state (OPC 30050 §6.3.3) and marked when faulted.
// Layout coordinates are metres on the floor with y up; the drawing flips y.
import {el} from './ui.js';

// How a PackML state reads at a glance.
const TONES = {
  Execute: 'ok',
  Held: 'warn', Holding: 'warn', Unholding: 'warn', Suspended: 'warn', Suspending: 'warn', Unsuspending: 'warn',
  Stopping: 'warn', Clearing: 'warn',
  Aborting: 'bad', Aborted: 'bad',
};

export function tone(machine) {
  if (!machine || machine.connected === false) return 'off';
  if (machine.fault) return 'bad';
  return TONES[machine.state] || 'idle';
}

const xy = (p) => (Array.isArray(p) ? [Number(p[0]), Number(p[1])] : [Number(p.x), Number(p.y)]);

// The point `at` metres along a polyline.
function along(points, at) {
  let left = Number(at) || 0;
  for (let i = 1; i < points.length; i++) {
    const [x0, y0] = points[i - 1];
    const [x1, y1] = points[i];
    const length = Math.hypot(x1 - x0, y1 - y0);
    if (left <= length && length > 0) return [x0 + ((x1 - x0) * left) / length, y0 + ((y1 - y0) * left) / length];
    left -= length;
  }
  return points[points.length - 1];
}

// The layout as belts {name, label, points, stations: [{name, at}]} and machines {name, label, at}:
// /api/layout's belts (path, stations with at_m or point) and machines (at their first station),
// or a layout file's robots (base), uploader and downloader.
export function normalizeLayout(raw) {
  const stationAt = new Map();
  const belts = (raw.belts || raw.conveyors || []).map((b) => {
    const points = (b.path || b.points || []).map(xy);
    const stations = (b.stations || []).map((s) => ({name: s.name,
      at: s.point ? xy(s.point) : s.at ? xy(s.at) : along(points, s.at_m)}));
    for (const s of stations) stationAt.set(`${b.name}/${s.name}`, s.at);
    // A belt's name alone is the place where it takes boxes over from the belt before it.
    if (points.length) stationAt.set(b.name, points[0]);
    return {name: b.name, label: b.label || b.name, points, stations};
  });
  const place = (m, offset) => {
    if (m.at || m.position) return xy(m.at || m.position);
    if (m.base) return xy(m.base);
    const station = m.station || (m.stations || [])[0];
    const at = station && stationAt.get(station);
    return at ? [at[0], at[1] + offset] : null;
  };
  const machines = [];
  const add = (m, kind, offset) => {
    if (!m || !m.name) return;
    const at = place(m, offset);
    if (at) machines.push({name: m.name, label: m.label || m.name, kind: m.kind || kind, at});
  };
  for (const r of raw.robots || []) add(r, 'robot', 0.4);
  add(raw.uploader, 'uploader', -0.4);
  add(raw.downloader, 'downloader', -0.4);
  // Transfers below their belt, robots above it.
  for (const m of raw.machines || []) add(m, 'machine', ['uploader', 'downloader'].includes(m.kind) ? -0.4 : 0.4);
  return {belts, machines, stations: stationAt};
}

const BOX = 0.16;

// Where a box is drawn: at its place, or a third of the way to the next stop of its route while
// a conveyor carries it there (the steps tell where it goes, not how far it got).
function boxPoint(stations, place) {
  const at = stations.get(place.at);
  if (!at) return null;
  const next = place.route && place.route.length ? stations.get(place.route[0].to) : null;
  return next ? [at[0] + (next[0] - at[0]) / 3, at[1] + (next[1] - at[1]) / 3] : at;
}

function boxTitle(order) {
  const p = order.place;
  const next = p.route && p.route.length ? `, next on ${p.route[0].conveyor} to ${p.route[0].to}` : '';
  return `box ${p.box} of order ${order.id} at ${p.at}${next}`;
}

function bounds(layout) {
  const all = [...layout.belts.flatMap((b) => b.points), ...layout.machines.map((m) => m.at)];
  const xs = all.map((p) => p[0]);
  const ys = all.map((p) => -p[1]);
  const pad = 0.5;
  const minX = Math.min(...xs) - pad;
  const minY = Math.min(...ys) - pad;
  return `${minX} ${minY} ${Math.max(...xs) + 2 * pad - minX} ${Math.max(...ys) + pad - minY}`;
}

const pathText = (points) => points.map(([x, y], i) => `${i ? 'L' : 'M'}${x} ${-y}`).join(' ');

function arrow(points) {
  const [x0, y0] = points[points.length - 2];
  const [x1, y1] = points[points.length - 1];
  const [mx, my] = [(x0 + x1) / 2, -(y0 + y1) / 2];
  const angle = (Math.atan2(-(y1 - y0), x1 - x0) * 180) / Math.PI;
  return el('path', {class: 'belt-arrow', d: 'M0.12 0 L-0.08 0.08 L-0.08 -0.08 Z',
    transform: `translate(${mx} ${my}) rotate(${angle})`});
}

// Draws the layout into `container`; onSelect(name) when a machine or belt is clicked. Returns
// {update(machine)} to recolour one machine from its state.
export function drawSchematic(container, rawLayout, onSelect) {
  const layout = normalizeLayout(rawLayout);
  const svg = el('svg', {viewBox: bounds(layout), role: 'img', 'aria-label': 'schematic of the line'});
  const nodes = new Map();
  const select = (name) => () => onSelect(name);
  for (const b of layout.belts) {
    if (b.points.length < 2) continue;
    const length = b.points.slice(1).reduce((sum, p, i) => sum + Math.hypot(p[0] - b.points[i][0], p[1] - b.points[i][1]), 0);
    const tag = along(b.points, length * 0.15);
    const g = el('g', {class: 'node conveyor', dataset: {machine: b.name}, on: {click: select(b.name)}},
      el('title', {text: b.label}),
      el('path', {class: 'belt', d: pathText(b.points)}),
      el('path', {d: pathText(b.points), stroke: 'transparent', 'stroke-width': 0.35, fill: 'none'}),
      arrow(b.points),
      b.stations.map((s) => el('circle', {class: 'station', cx: s.at[0], cy: -s.at[1], r: 0.07})),
      el('text', {class: 'belt-label', x: tag[0] + 0.1, y: -tag[1] - 0.12, text: b.label}));
    svg.append(g);
    nodes.set(b.name, g);
  }
  for (const m of layout.machines) {
    const [x, y] = m.at;
    const w = Math.max(0.8, 0.085 * m.name.length + 0.15);
    const g = el('g', {class: `node ${m.kind}`, dataset: {machine: m.name}, on: {click: select(m.name)}},
      el('title', {text: m.label}),
      el('rect', {x: x - w / 2, y: -y - 0.15, width: w, height: 0.3, rx: 0.05}),
      el('text', {x, y: -y + 0.05, 'text-anchor': 'middle', text: m.name}));
    svg.append(g);
    nodes.set(m.name, g);
  }
  const boxes = el('g', {class: 'boxes'});
  svg.append(boxes);
  container.replaceChildren(svg);
  return {
    // Draws the boxes of the orders in work (each order with its `place`); several at one spot
    // side by side.
    boxes(orders) {
      const taken = new Map();
      const marks = [];
      for (const order of orders) {
        if (!order.place) continue;
        const point = boxPoint(layout.stations, order.place);
        if (!point) continue;
        const key = point.join(',');
        const n = taken.get(key) || 0;
        taken.set(key, n + 1);
        const moving = !!(order.place.route && order.place.route.length);
        marks.push(el('rect', {class: 'box', x: point[0] - BOX / 2 + n * BOX * 1.2, y: -point[1] - BOX / 2,
          width: BOX, height: BOX, rx: 0.02, dataset: {order: order.id, box: String(order.place.box), at: order.place.at,
            moving: String(moving)}}, el('title', {text: boxTitle(order)})));
      }
      boxes.replaceChildren(...marks);
    },
    update(machine) {
      const g = nodes.get(machine.name);
      if (!g) return;
      g.dataset.state = machine.state || '';
      g.dataset.tone = tone(machine);
      g.classList.toggle('fault', !!machine.fault);
      const belt = g.querySelector('path.belt');
      if (belt) belt.dataset.tone = tone(machine);
      g.querySelector('title').textContent =
        `${machine.name}: ${machine.state || 'unknown'}${machine.fault ? ` (fault: ${machine.fault})` : ''}`;
    },
    select(name) {
      for (const [key, g] of nodes) g.classList.toggle('selected', key === name);
    },
  };
}
