// The knowledge loop's alarms: each violation the reasoner found, with its rule, message and the
// matched facts (the explanation: the triples that made the rule fire), live on topic `alarms`,
// acknowledged by an operator with an optional comment.
import * as api from './api.js';
import {$, clear, el, guard, millis, notify, time} from './ui.js';

// An individual's IRI as people read it: its local name (…/prototype/Conveyor3 → Conveyor3).
function shortName(iri) {
  return String(iri || '').replace(/^.*[/#]/, '') || String(iri || '');
}

export class AlarmList {
  constructor(live, session) {
    this.session = session;
    this.alarms = new Map();  // id → alarm
    live.subscribe('alarms', (value) => this.receive(value));
    live.on('open', guard(() => this.load()));
  }

  async load() {
    const list = await api.alarms({active: true});
    this.alarms = new Map(list.map((a) => [a.id, a]));
    this.render();
  }

  // The stream sends the active alarms as a list (an acknowledgement this page knows of is kept
  // when the list leaves it out), or one alarm that was raised, changed or cleared.
  receive(value) {
    const list = Array.isArray(value) ? value : value && Array.isArray(value.alarms) ? value.alarms : null;
    if (list) {
      this.alarms = new Map(list.map((a) => [a.id, {...this.known(a.id), ...a}]));
    } else if (value && value.id !== undefined) {
      this.alarms.set(value.id, {...this.alarms.get(value.id), ...value});
    }
    this.render();
  }

  known(id) {
    const before = this.alarms.get(id);
    return before && before.acked ? {acked: true, acked_by: before.acked_by, ack_comment: before.ack_comment} : {};
  }

  async acknowledge(alarm, comment) {
    const acked = await api.acknowledge(alarm.id, comment);
    this.alarms.set(alarm.id, {...alarm, ...(acked || {acked: true, acked_by: this.session.user})});
    notify(`alarm ${alarm.rule} on ${alarm.entity} acknowledged`);
    this.render();
  }

  card(alarm) {
    const mayOperate = api.mayOperate(this.session.role);
    const comment = el('input', {class: 'ack-comment', placeholder: 'comment', 'aria-label': 'comment'});
    const state = alarm.active === false ? 'cleared' : alarm.acked ? 'acked' : 'active';
    return el('article', {class: `alarm ${state}`, dataset: {alarm: alarm.id, rule: alarm.rule, entity: alarm.entity,
      state}},
    el('header', {},
      el('span', {class: 'rule', text: alarm.rule}),
      el('span', {class: 'entity', text: shortName(alarm.entity), title: alarm.entity}),
      el('time', {text: time(alarm.time)}),
      el('span', {class: 'state', text: state})),
    el('p', {class: 'alarm-message', text: alarm.message}),
    el('details', {open: true},
      el('summary', {text: `why: ${(alarm.facts || []).length} facts`}),
      el('ul', {class: 'facts-list'}, (alarm.facts || []).map((f) => el('li', {text: f})))),
    alarm.acked ?
      el('p', {class: 'note acked-by', text: `acknowledged by ${alarm.acked_by || '?'}${alarm.ack_comment ?
        `: ${alarm.ack_comment}` : ''}`}) :
      el('div', {class: 'toolbar'}, comment, el('button', {type: 'button', class: 'ack', text: 'Acknowledge',
        disabled: !mayOperate, title: mayOperate ? '' : 'operators only',
        on: {click: guard(() => this.acknowledge(alarm, comment.value))}})));
  }

  render() {
    const list = [...this.alarms.values()].sort((a, b) => millis(b.time) - millis(a.time));
    // The same alarms again (the stream repeats the list): the cards stay, with what was typed.
    const signature = JSON.stringify(list);
    if (signature === this.shown) return;
    this.shown = signature;
    const active = list.filter((a) => a.active !== false).length;
    $('#alarm-count').textContent = String(active);
    $('#alarm-count').dataset.state = active ? 'failed' : 'done';
    clear($('#alarm-list'), list.length ? list.map((a) => this.card(a)) : el('p', {class: 'note', text: 'No alarms.'}));
  }
}
