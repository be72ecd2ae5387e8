// The Contract Net of an order as a timeline (paper §V, FIPA Contract Net: announce, bids,
// award, then the route and the transports), from /api/orders/{id}/negotiation.
import * as api from './api.js';
import {$, clear, el, guard, time} from './ui.js';

// What kind of step of the protocol a step is, for its colour.
function kind(what) {
  if (/announce/i.test(what)) return 'announce';
  if (/bid|propos/i.test(what)) return 'bid';
  if (/award|accepted|routed/i.test(what)) return 'award';
  if (/fail|refus|reject|cancel/i.test(what)) return 'failure';
  return 'step';
}

export class NegotiationPanel {
  constructor() {
    const show = guard(() => this.show($('#negotiation-order').value));
    $('#negotiation-load').addEventListener('click', show);
    $('#negotiation-order').addEventListener('change', show);
  }

  async loadOrders() {
    const list = await api.orders({limit: 50});
    const chosen = $('#negotiation-order').value;
    clear($('#negotiation-order'), list.map((o) => el('option', {value: o.id, text: `${o.id} (${o.state})`,
      selected: o.id === chosen})));
    if ($('#negotiation-order').value) await this.show($('#negotiation-order').value);
  }

  async show(id) {
    if (!id) return;
    const steps = await api.negotiation(id);
    $('#timeline').dataset.order = id;
    clear($('#timeline'), steps.length ? steps.map((s) => el('li', {dataset: {kind: kind(s.what), what: s.what}},
      el('time', {text: time(s.time)}), ' ', el('strong', {text: s.what}), s.machine ? ` ${s.machine}` : '',
      s.detail ? el('span', {class: 'detail', text: ` ${s.detail}`}) : null)) :
      el('li', {class: 'note', text: 'no negotiation yet'}));
  }
}
