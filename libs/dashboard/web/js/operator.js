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

function machineRow(m) {
  const job = m.job && m.job.id ? `${m.job.id} ${m.job.operation || ''}`.trim() : '';
  return el('tr', {dataset: {machine: m.name, state: m.state || '', tone: tone(m)}},
    el('td', {}, el('button', {type: 'button', class: 'link', text: m.name, dataset: {select: m.name}})),
    el('td', {class: 'state-cell', text: m.connected === false ? 'not connected' : m.state || ''}),
    el('td', {text: m.mode || ''}), el('td', {text: job}),
    el('td', {class: 'num', text: m.processed ?? ''}), el('td', {class: 'num', text: m.defective ?? ''}),
    el('td', {class: 'fault-cell', text: m.fault || ''}));
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

  const render = () => clear($('#machines tbody'),
    [...machines.values()].sort((a, b) => a.name.localeCompare(b.name)).map(machineRow));
  // The list, or one machine that changed.
  const receive = (value) => {
    for (const m of Array.isArray(value) ? value : [value]) {
      if (!m || !m.name) continue;
      const merged = {...machines.get(m.name), ...m};
      machines.set(m.name, merged);
      schematic.update(merged);
      panel.update(merged);
    }
    render();
  };
  live.subscribe('machines', receive);
  const reload = guard(async () => receive(await api.machines()));
  live.on('open', reload);
  await reload();

  const alarms = new AlarmList(live, session);
  const oee = new OeePanel();
  const negotiation = new NegotiationPanel();
  live.start();
  await Promise.all([guard(() => alarms.load())(), guard(() => oee.load())(), guard(() => negotiation.loadOrders())()]);
}

guard(() => startSession(guard(openDesk)))();
