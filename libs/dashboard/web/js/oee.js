// OEE per machine and of the line over a range (ISO 22400-2: availability × performance ×
// quality from the PackML Admin counters, docs/dashboard.md "OEE"), with the line's trend in
// buckets of the range. An undefined factor (no data, a zero denominator) shows as –, never 0.
import * as api from './api.js';
import {timeChart} from './chart.js';
import {$, clear, el, guard, millis, percent} from './ui.js';

const BUCKETS = 24;

function row(name, o, cls) {
  const cells = ['availability', 'performance', 'quality', 'oee'].map((k) =>
    el('td', {class: 'num', text: percent(o[k]), dataset: {k}}));
  return el('tr', {class: cls, dataset: {machine: name}}, el('th', {text: name}), cells,
    el('td', {class: 'num', text: o.produced ?? '–'}), el('td', {class: 'num', text: o.defective ?? '–'}));
}

export class OeePanel {
  constructor() {
    this.chart = null;
    const refresh = guard(() => this.load());
    $('#oee-load').addEventListener('click', refresh);
    $('#oee-range').addEventListener('change', refresh);
  }

  async load() {
    const to = Date.now();
    const from = to - Number($('#oee-range').value);
    const result = await api.oee({from, to, buckets: BUCKETS});
    const machines = result.machines || [];
    clear($('#oee-table tbody'), machines.map((o) => row(o.machine, o)),
      result.line ? row(`line${result.line.machine ? ` (${result.line.machine})` : ''}`, result.line, 'line-total') : null);
    const trend = result.trend || [];
    if (!this.chart) {
      this.chart = timeChart($('#oee-trend'), [{label: 'OEE'}, {label: 'availability', width: 1},
        {label: 'performance', width: 1}, {label: 'quality', width: 1}], {percent: true, height: 180});
    }
    // A bucket's time: its own when the server gives one, else its start in the range.
    const step = (to - from) / Math.max(1, trend.length);
    const times = trend.map((o, k) => (o.from !== undefined ? millis(o.from) : o.t !== undefined ? millis(o.t) :
      from + k * step));
    this.chart.setData(times, ['oee', 'availability', 'performance', 'quality'].map((key) =>
      trend.map((o) => (o[key] === undefined ? null : o[key]))));
  }
}
