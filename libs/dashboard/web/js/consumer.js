// The consumer's page (paper Fig. 1: personalised candy boxes ordered from a phone or computer):
// log in, put a box together from the catalog, place it, then follow the order live as the line
// negotiates, routes, loads and inspects it.
import * as api from './api.js';
import {Live} from './live.js';
import {checkOrder} from './order_check.js';
import {$, clear, el, guard, showLiveState, startSession, time} from './ui.js';

// The steps a box goes through (openapi.yaml OrderStep.what), in order.
const MILESTONES = ['accepted', 'awarded', 'routed', 'loaded', 'inspected', 'done'];
const ENDINGS = new Set(['done', 'failed', 'cancelled']);

const live = new Live();
let catalog = {box_types: [], candy_types: []};
let following = null;  // {id, unsubscribe}

function candySelect(selected) {
  return el('select', {class: 'candy', 'aria-label': 'candy type'},
    catalog.candy_types.map((c) => el('option', {value: c.name, text: c.label || c.name, selected: c.name === selected})));
}

function addLine(candy, quantity = 1) {
  const row = el('div', {class: 'line'},
    candySelect(candy),
    el('input', {class: 'quantity', type: 'number', min: 1, step: 1, value: quantity, inputmode: 'numeric',
      'aria-label': 'quantity'}),
    el('button', {type: 'button', class: 'remove', text: 'Remove', on: {click: () => { row.remove(); recheck(); }}}));
  $('#lines').append(row);
  recheck();
}

function entered() {
  return [...document.querySelectorAll('#lines .line')].map((row) => ({
    candy: row.querySelector('.candy').value,
    quantity: row.querySelector('.quantity').value,
  }));
}

// Shows what is wrong with the order as entered; the request when nothing is.
function recheck() {
  const box = $('#box').value;
  const result = checkOrder(catalog, box, entered());
  const boxType = catalog.box_types.find((b) => b.name === box);
  $('#fill').textContent = boxType ? `${result.total} of ${boxType.capacity} places filled` : '';
  clear($('#order-errors'), result.errors.map((text) => el('li', {text})));
  $('#place').disabled = result.errors.length > 0;
  return result.request;
}

async function loadCatalog() {
  catalog = await api.catalog();
  clear($('#box'), catalog.box_types.map((b) =>
    el('option', {value: b.name, text: `${b.label || b.name} (${b.capacity} candies)`})));
  clear($('#lines'));
  if (catalog.candy_types.length) addLine(catalog.candy_types[0].name, 1);
}

function milestoneReached(order, what) {
  return order.steps.some((s) => s.what === what);
}

function inspectionText(inspection) {
  if (!inspection) return 'not yet';
  const counted = Object.entries(inspection.counted || {}).map(([k, n]) => `${n} ${k}`).join(', ');
  const verdict = inspection.matches === false ? 'does not match the order' : 'matches the order';
  const weight = inspection.weight_g !== undefined ? `, ${inspection.weight_g} g` : '';
  return `box ${inspection.box ?? ''}: ${counted || 'empty'}${weight}; ${verdict}`;
}

function showOrder(order) {
  order.steps = order.steps || [];
  $('#tracking').hidden = false;
  $('#tracking').dataset.state = order.state;
  $('#order-id').textContent = order.id;
  $('#order-state').textContent = order.state;
  $('#order-state').dataset.state = order.state;
  const failed = order.steps.find((s) => s.what === 'failed' || s.what === 'cancelled');
  clear($('#milestones'), MILESTONES.map((what) => el('li', {
    text: what, class: milestoneReached(order, what) ? 'reached' : '', dataset: {step: what}})),
  failed ? el('li', {text: failed.what, class: 'reached bad', dataset: {step: failed.what}}) : null);
  const candy = Object.entries(order.candy || {}).map(([k, n]) => `${n} ${k}`).join(', ');
  $('#order-box').textContent = `${order.box || ''}: ${candy}`;
  $('#order-machines').textContent = (order.machines || []).join(', ') || 'none yet';
  $('#order-inspection').textContent = inspectionText(order.inspection);
  $('#order-inspection').dataset.matches = order.inspection ? String(order.inspection.matches !== false) : '';
  clear($('#steps'), order.steps.map((s) => el('li', {dataset: {what: s.what}},
    el('time', {text: time(s.time)}), ' ', el('strong', {text: s.what}),
    s.machine ? ` ${s.machine}` : '', s.detail ? el('span', {class: 'detail', text: ` ${s.detail}`}) : null)));
  $('#cancel').hidden = !['submitted', 'queued'].includes(order.state);
}

// A live update of the followed order: the whole order, or one new step of it.
function onOrderUpdate(id, update) {
  if (!following || following.id !== id || !update) return;
  if (Array.isArray(update.steps)) {
    following.order = update;
  } else if (update.what) {
    following.order.steps = [...following.order.steps, update];
    if (ENDINGS.has(update.what)) following.order.state = update.what;
  } else {
    following.order = {...following.order, ...update};
  }
  showOrder(following.order);
  if (ENDINGS.has(following.order.state)) loadMyOrders();
}

const follow = guard(async (id) => {
  if (following) following.unsubscribe();
  const order = await api.order(id);
  following = {id, order, unsubscribe: live.subscribe(`order/${id}`, (value) => onOrderUpdate(id, value))};
  showOrder(order);
});

const loadMyOrders = guard(async () => {
  const list = await api.orders({limit: 20});
  $('#history').hidden = list.length === 0;
  clear($('#my-orders'), list.map((o) => el('li', {},
    el('button', {type: 'button', class: 'link', text: `${o.id} · ${o.box || ''} · ${o.state}`,
      on: {click: () => follow(o.id)}}))));
});

function wire() {
  $('#add-line').addEventListener('click', () => {
    const used = new Set(entered().map((l) => l.candy));
    const next = catalog.candy_types.find((c) => !used.has(c.name));
    addLine(next ? next.name : catalog.candy_types[0].name, 1);
  });
  $('#order').addEventListener('input', recheck);
  $('#order').addEventListener('change', recheck);
  $('#order').addEventListener('submit', guard(async (event) => {
    event.preventDefault();
    const request = recheck();
    if (!request) return;
    $('#place').disabled = true;
    try {
      const order = await api.placeOrder(request.box, request.candy);
      await follow(order.id);
      loadMyOrders();
    } finally {
      recheck();
    }
  }));
  $('#cancel').addEventListener('click', guard(async () => {
    if (following) await api.cancelOrder(following.id);
  }));
  // What happened while the stream was away comes with the order itself.
  live.on('open', guard(async () => {
    if (!following) return;
    const id = following.id;
    const order = await api.order(id);
    if (following && following.id === id) onOrderUpdate(id, order);
  }));
}

wire();
showLiveState(live);
guard(async () => {
  await guard(loadCatalog)();
  await startSession(() => {
    $('#order').hidden = false;
    recheck();
    live.start();
    loadMyOrders();
  });
})();
