// The operator's page (paper §VII client terminals): the line as a schematic with live machine
// states, one machine in detail with its commands and trends, the alarms with their
// explanations, OEE and the Contract Net of an order.
import * as api from './api.js';
import {AlarmList} from './alarms.js';
import {Live} from './live.js';
import {MachinePanel} from './machine.js';
import {NegotiationPanel} from './negotiation.js';
import {OeePanel} from './oee.js';
import {drawSchematic, tone} from './schematic.js';
import {$, clear, el, guard, showLiveState, startSession} from './ui.js';

const live = new Live();
showLiveState(live);

// The machine list: one row per machine, updated in place (a row rebuilt on every update would
// take the button away from under the pointer).
class MachineTable {
  constructor(body) {
    this.body = body;
    this.rows = new Map();
  }

  row(name) {
    let tr = this.rows.get(name);
    if (!tr) {
      tr = el('tr', {dataset: {machine: name}},
        el('td', {}, el('button', {type: 'button', class: 'link', text: name, dataset: {select: name}})),
        ...['state-cell', 'mode', 'job', 'num processed', 'num defective', 'fault-cell'].map((c) => el('td', {class: c})));
      this.rows.set(name, tr);
      const names = [...this.rows.keys()].sort();
      clear(this.body, names.map((n) => this.rows.get(n)));
    }
    return tr;
  }

  update(m) {
    const tr = this.row(m.name);
    const cells = tr.children;
    const job = m.job && m.job.id ? `${m.job.id} ${m.job.operation || ''}`.trim() : '';
    const texts = [m.connected === false ? 'not connected' : m.state || '', m.mode || '', job, m.processed ?? '',
      m.defective ?? '', m.fault || ''];
    texts.forEach((text, i) => {
      if (cells[i + 1].textContent !== String(text)) cells[i + 1].textContent = String(text);
    });
    tr.dataset.state = m.state || '';
    tr.dataset.tone = tone(m);
  }
}

async function openDesk(session) {
  $('#desk').hidden = false;
  const machines = new Map();
  const panel = new MachinePanel(live, session);
  const select = guard(async (name) => {
    schematic.select(name);
    await panel.show(name);
  });
  const schematic = drawSchematic($('#schematic'), await api.layout(), select);
  $('#machines tbody').addEventListener('click', (event) => {
    const name = event.target.dataset && event.target.dataset.select;
    if (name) select(name);
  });

  const table = new MachineTable($('#machines tbody'));
  // The list, or one machine that changed.
  const receive = (value) => {
    for (const m of Array.isArray(value) ? value : [value]) {
      if (!m || !m.name) continue;
      const merged = {...machines.get(m.name), ...m};
      machines.set(m.name, merged);
      schematic.update(merged);
      table.update(merged);
      panel.update(merged);
    }
  };
  live.subscribe('machines', receive);
  const reload = guard(async () => receive(await api.machines()));
  live.on('open', reload);
  await reload();

  // The boxes on the belts and stations: every order in work with its box's place.
  const inWork = new Map();
  const drawBoxes = () => schematic.boxes([...inWork.values()]);
  const followOrder = (order) => {
    if (!order || !order.id) return;
    if (order.state === 'in work' && order.place) inWork.set(order.id, order);
    else inWork.delete(order.id);
    drawBoxes();
  };
  live.subscribe('orders', followOrder);
  const reloadBoxes = guard(async () => {
    inWork.clear();
    for (const order of await api.orders({state: 'in work', limit: 200})) followOrder(order);
    drawBoxes();
  });
  live.on('open', reloadBoxes);
  await reloadBoxes();

  const alarms = new AlarmList(live, session);
  const oee = new OeePanel();
  const negotiation = new NegotiationPanel();
  live.start();
  await Promise.all([guard(() => alarms.load())(), guard(() => oee.load())(), guard(() => negotiation.loadOrders())()]);
}

guard(() => startSession(guard(openDesk)))();
