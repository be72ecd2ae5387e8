// One machine in detail: its PackML state and current values (live on topic machine/<name>),
// the PackML commands through its OPC UA methods (OPC 30050 §6.3.6-8; operator, engineer and
// admin only: a viewer sees them disabled and the server refuses anyway), and the trend of one of
// its series from the historian's aggregates.
import * as api from './api.js';
import {timeChart} from './chart.js';
import {$, clear, el, guard, millis, notify, time, value} from './ui.js';

const COMMANDS = ['Start', 'Stop', 'Hold', 'Unhold', 'Reset', 'Clear', 'Abort'];

// Which commands the PackML state machine takes in a state (ISA-TR88.00.02 Figure 1; Stop and
// Abort from every state their transitions name). Others are shown disabled.
const ALLOWED = {
  Idle: ['Start', 'Stop', 'Abort'],
  Stopped: ['Reset', 'Abort'],
  Complete: ['Reset', 'Stop', 'Abort'],
  Execute: ['Hold', 'Stop', 'Abort'],
  Held: ['Unhold', 'Stop', 'Abort'],
  Suspended: ['Stop', 'Abort'],
  Aborted: ['Clear'],
};

// The series a machine's trend shows first: motion, then the PackML state.
const TREND_FIRST = [/speed$/, /position$/, /odometer$/, /temperature/i, /PackML\/Status\/StateCurrent$/];

export class MachinePanel {
  constructor(live, session) {
    this.live = live;
    this.session = session;
    this.name = null;
    this.machine = null;
    this.unsubscribe = null;
    this.range = null;  // {from, to} in ms of the trend shown
    this.chart = null;
    this.wire();
  }

  wire() {
    clear($('#commands'), COMMANDS.map((command) => el('button', {
      type: 'button', text: command, dataset: {command},
      on: {click: guard(() => this.command(command))}})));
    const mayOperate = api.mayOperate(this.session.role);
    $('#command-note').hidden = mayOperate;
    $('#command-note').textContent = `Your role (${this.session.role}) may watch but not command the machines.`;
    const refresh = guard(() => this.loadTrend());
    $('#trend-range').addEventListener('change', () => {
      $('#trend-custom').hidden = $('#trend-range').value !== 'custom';
      if ($('#trend-range').value !== 'custom') refresh();
    });
    $('#trend-load').addEventListener('click', refresh);
    $('#trend-series').addEventListener('change', refresh);
  }

  async show(name) {
    if (this.unsubscribe) this.unsubscribe();
    this.name = name;
    $('#machine').hidden = false;
    $('#machine-name').textContent = name;
    this.render(await api.machine(name));
    this.unsubscribe = this.live.subscribe(`machine/${name}`, (m) => { if (m && m.name === this.name) this.render(m); });
    const list = await api.series({server: name});
    const chosen = TREND_FIRST.map((re) => list.find((s) => re.test(s.browse_path))).find(Boolean) || list[0];
    clear($('#trend-series'), list.map((s) => el('option', {value: s.id, selected: s === chosen,
      text: `${s.browse_path.replace(/^\/Objects\/Machines\/[^/]+\//, '')}${s.unit ? ` [${s.unit}]` : ''}`})));
    await this.loadTrend();
  }

  // A machine from the list or the stream (missing values kept from before). The stream's
  // updates carry the summary only: the current values are fetched again, at most once a second.
  update(machine) {
    if (!machine || machine.name !== this.name) return;
    this.render({...this.machine, ...machine});
    if (this.refetch) return;
    this.refetch = setTimeout(guard(async () => {
      const name = this.name;
      try {
        const detail = await api.machine(name);
        if (name === this.name) this.render({...detail, ...this.latest()});
      } finally {
        this.refetch = null;
      }
    }), 1000);
  }

  // The stream's summary is newer than a fetched detail's: it wins, the detail adds the values.
  latest() {
    const keys = ['state', 'mode', 'fault', 'connected', 'processed', 'defective', 'job'];
    return Object.fromEntries(keys.filter((k) => this.machine && k in this.machine).map((k) => [k, this.machine[k]]));
  }

  render(machine) {
    this.machine = machine;
    const state = machine.connected === false ? 'not connected' : machine.state || 'unknown';
    $('#machine-state').textContent = state;
    $('#machine').dataset.state = machine.state || '';
    $('#machine-fault').hidden = !machine.fault;
    $('#machine-fault').textContent = machine.fault ? `Fault: ${machine.fault}` : '';
    const mayOperate = api.mayOperate(this.session.role);
    const allowed = ALLOWED[machine.state];
    for (const button of document.querySelectorAll('#commands button')) {
      const command = button.dataset.command;
      button.disabled = !mayOperate || machine.connected === false || (allowed ? !allowed.includes(command) : false);
      button.title = mayOperate ? '' : 'operators only';
    }
    const rows = [
      ['PackML state', machine.state], ['Mode', machine.mode], ['Kind', machine.kind], ['Server', machine.server],
      ['Job', machine.job && machine.job.id ?
        `${machine.job.id} ${machine.job.operation || ''} (${machine.job.queued ?? 0} queued)` : ''],
      ['Processed', machine.processed], ['Defective', machine.defective],
      ...Object.entries(machine.values || {}).sort(([a], [b]) => a.localeCompare(b)),
    ];
    // A current value comes as {value, time} (the source time of its sample) or bare.
    const shown = (v) => (v && typeof v === 'object' && 'value' in v ? value(v.value) : value(v));
    const when = (v) => (v && typeof v === 'object' && v.time ? time(v.time) : '');
    clear($('#machine-values tbody'), rows.filter(([, v]) => v !== undefined && v !== null && v !== '').map(([k, v]) =>
      el('tr', {dataset: {path: k}}, el('th', {text: k}), el('td', {text: shown(v)}), el('td', {class: 'note', text: when(v)}))));
  }

  async command(command) {
    if (!this.name) return;
    await api.command(this.name, command);
    notify(`${this.name} took ${command}`);
    this.render(await api.machine(this.name));
  }

  pickedRange() {
    const choice = $('#trend-range').value;
    if (choice === 'custom') {
      const from = new Date($('#trend-from').value).getTime();
      const to = new Date($('#trend-to').value).getTime();
      if (!Number.isFinite(from) || !Number.isFinite(to) || from >= to) throw new Error('choose a start before the end');
      return {from, to};
    }
    const to = Date.now();
    return {from: to - Number(choice), to};
  }

  async loadTrend(range) {
    const id = $('#trend-series').value;
    if (!id) return;
    try {
      this.range = range || this.pickedRange();
    } catch (e) {
      notify(e.message, 'error');
      return;
    }
    if (!this.chart) {
      this.chart = timeChart($('#trend'), [{label: 'avg'}, {label: 'min', dash: [4, 4], width: 1},
        {label: 'max', dash: [4, 4], width: 1}], {
        onZoom: (from, to) => guard(() => this.loadTrend({from, to}))(),
        onReset: () => guard(() => this.loadTrend())(),
      });
    }
    const intervals = await api.aggregate(id, {from: Math.round(this.range.from), to: Math.round(this.range.to),
      points: 400});
    $('#trend').dataset.points = String(intervals.length);
    $('#trend').dataset.series = id;
    this.chart.setData(intervals.map((a) => millis(a.t)),
      [intervals.map((a) => a.avg ?? null), intervals.map((a) => a.min ?? null), intervals.map((a) => a.max ?? null)]);
  }
}
