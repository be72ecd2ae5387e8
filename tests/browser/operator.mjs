// An operator at the line: sees the schematic with live machine states, a machine turn Aborted
// through the live stream when a fault is injected in the plant, the knowledge loop's alarm with
// its explanation (rule, message, facts), acknowledges it, clears and resets the machine, starts
// it, holds and unholds it; the machine's trend (zoomed by dragging), OEE and the Contract Net of
// an order are on the page.
import {execFileSync} from 'node:child_process';
import {check, checkNoProblems, login, messages, newPage, note, open, pageFetch, scenario, screenshot, waitLive}
  from './browser.mjs';

const extra = {
  'sf-bin': {type: 'string'},
  'plant-control': {type: 'string'},
  machine: {type: 'string', default: 'conveyor3'},
  fault: {type: 'string', default: 'jam:conveyor3'},
};

function plantFault(opts, action) {
  execFileSync(opts['sf-bin'], ['plant', 'faults', '--control', opts['plant-control'], action, opts.fault],
    {stdio: 'inherit'});
  note(`plant fault ${opts.fault}: ${action}`);
}

const stateOf = (page, name) => page.$eval(`#schematic [data-machine="${name}"]`, (g) => g.dataset.state);

async function waitState(page, name, state) {
  await page.waitForSelector(`#schematic [data-machine="${name}"][data-state="${state}"]`);
  await page.waitForSelector(`#machine[data-state="${state}"]`);
}

async function command(page, name, cmd, next) {
  await page.waitForSelector(`#commands button[data-command=${cmd}]:not([disabled])`);
  await page.click(`#commands button[data-command=${cmd}]`);
  await waitState(page, name, next);
  check(await stateOf(page, name) === next, `${cmd}: ${name} is ${next} on the page`);
}

await scenario(async (browser, opts) => {
  const name = opts.machine;
  const page = await newPage(browser);
  let machineGets = 0;
  page.on('request', (r) => { if (new URL(r.url()).pathname === '/api/machines') machineGets += 1; });
  await open(page, `${opts.url}/operator.html`);
  await login(page, opts.user, opts.password);
  await page.waitForSelector(`#schematic [data-machine="${name}"]`);
  await waitLive(page);
  const drawn = await page.$$eval('#schematic [data-machine]', (nodes) => nodes.map((n) => n.dataset.machine));
  const listed = (await pageFetch(page, 'GET', '/api/machines')).body.map((m) => m.name);
  check(listed.every((m) => drawn.includes(m)), `the schematic draws every machine and conveyor: ${drawn.join(', ')}`);
  await page.waitForSelector(`#schematic [data-machine="${name}"][data-state=Execute]`);
  await page.waitForSelector('#oee-table tbody tr');

  // An order in work: its box drawn on the schematic where its steps put it, on a station of the
  // layout, and gone once the order is done.
  const placed = await pageFetch(page, 'POST', '/api/orders', {body: {box: 'small-box', candy: {gummy: 1}}});
  check(placed.status === 201, `the operator places an order to watch its box: ${JSON.stringify(placed.body)}`);
  const boxMark = `#schematic rect.box[data-order="${placed.body.id}"]`;
  await page.waitForSelector(boxMark, {timeout: 600000});
  // Places: a belt's stations, and a belt's name alone (where it takes boxes over).
  const places = (await pageFetch(page, 'GET', '/api/layout')).body.belts
    .flatMap((b) => [b.name, ...(b.stations || []).map((st) => `${b.name}/${st.name}`)]);
  const at = await page.$eval(boxMark, (r) => r.dataset.at);
  check(places.includes(at), `the box of ${placed.body.id} is drawn at a place of the layout: ${at}`);
  await screenshot(page, opts.screenshots, 'operator-line');
  // Every place it passes is drawn: the mark stays until the order ends, then goes.
  let order = placed.body;
  const until = Date.now() + 900000;
  while (!['done', 'failed'].includes(order.state) && Date.now() < until) {
    const drawn = await page.$(boxMark);
    order = (await pageFetch(page, 'GET', `/api/orders/${placed.body.id}`)).body;
    if (order.state === 'in work' && order.place && !drawn) {
      const again = await page.waitForSelector(boxMark, {timeout: 10000}).catch(() => null);
      check(again, `the box of ${placed.body.id} at ${order.place.at} is on the schematic`);
    }
    await new Promise((resolve) => setTimeout(resolve, 1000));
  }
  check(['done', 'failed'].includes(order.state) && !order.place, `the order ends (${order.state}) without a place`);
  await page.waitForSelector(boxMark, {hidden: true, timeout: 30000});
  note('its box left the schematic');

  // The machine in detail, with its trend.
  await page.click(`#machines button[data-select="${name}"]`);
  await page.waitForFunction((n) => document.querySelector('#machine-name').textContent === n &&
    !document.querySelector('#machine').hidden, {}, name);
  await page.waitForSelector('#trend .uplot');
  await page.waitForSelector('#trend[data-points]');
  // A series with something to zoom into: intervals with samples in the last hour.
  const series = await page.$$eval('#trend-series option', (options) => options.map((o) => [o.value, o.textContent]));
  let shown = null;
  for (const [id, label] of series) {
    await page.select('#trend-series', id);
    await page.waitForSelector(`#trend[data-series="${id}"]`);
    if (Number(await page.$eval('#trend', (t) => t.dataset.points)) >= 2) {
      shown = label;
      break;
    }
  }
  check(shown, `the trend of a series of ${name} from the historian: ${shown}`);
  const aggregates = [];
  page.on('request', (r) => { if (/\/aggregate\?/.test(r.url())) aggregates.push(new URL(r.url()).searchParams); });
  const over = await page.$('#trend .u-over');
  await over.scrollIntoView();
  const box = await over.boundingBox();
  await page.mouse.move(box.x + box.width * 0.5, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.9, box.y + box.height / 2, {steps: 5});
  await page.mouse.up();
  const zoomDeadline = Date.now() + 60000;
  while (aggregates.length === 0 && Date.now() < zoomDeadline) await new Promise((r) => setTimeout(r, 200));
  check(aggregates.length > 0, 'dragging across the trend asks the historian for the narrower range');
  const zoom = aggregates[0];
  note(`zoomed to ${zoom.get('from')} … ${zoom.get('to')}`);

  // A fault in the plant: the machine's state changes on the page through the live stream.
  const gets = machineGets;
  const opensBefore = Number(await page.$eval('#live', (e) => e.dataset.opens));
  plantFault(opts, 'inject');
  await waitState(page, name, 'Aborted');
  const opens = Number(await page.$eval('#live', (e) => e.dataset.opens));
  check(machineGets - gets <= opens - opensBefore, `${name} shows Aborted through the live stream ` +
    `(${machineGets - gets} list fetches, ${opens - opensBefore} reconnections)`);
  check(await page.$eval(`#schematic [data-machine="${name}"]`, (g) => g.dataset.tone) === 'bad', `${name} is marked faulted in the schematic`);

  // Its alarm with the explanation.
  const alarmSel = '#alarm-list .alarm[data-state=active]';
  await page.waitForFunction((sel, n) => [...document.querySelectorAll(sel)].some((a) =>
    `${a.dataset.entity} ${a.querySelector('.alarm-message').textContent}`.toLowerCase().includes(n.toLowerCase())),
  {timeout: 180000}, alarmSel, name);
  const alarm = await page.$$eval(alarmSel, (cards, n) => cards.map((a) => ({
    id: a.dataset.alarm, rule: a.dataset.rule, entity: a.dataset.entity, message: a.querySelector('.alarm-message').textContent,
    facts: [...a.querySelectorAll('.facts-list li')].map((li) => li.textContent),
  })).find((a) => `${a.entity} ${a.message}`.toLowerCase().includes(n.toLowerCase())), name);
  check(alarm.rule && alarm.message, `the alarm names its rule and says what is wrong: ${alarm.rule}: ${alarm.message}`);
  check(alarm.facts.length > 0, `the alarm explains itself with the facts that made its rule fire: ${alarm.facts.join(' | ')}`);
  await screenshot(page, opts.screenshots, 'operator-alarm');

  // Acknowledged by the operator.
  const card = `#alarm-list .alarm[data-alarm="${alarm.id}"]`;
  await page.type(`${card} .ack-comment`, 'belt cleared');
  await page.click(`${card} button.ack`);
  await page.waitForSelector(`${card} .acked-by, #messages .message.error`);
  check(await page.$(`${card} .acked-by`), `the page shows the alarm acknowledged: ${await messages(page)}`);
  const acked = (await pageFetch(page, 'GET', '/api/alarms')).body.find((a) => a.id === alarm.id);
  check(acked && acked.acked && acked.acked_by === opts.user, `the API has the alarm acknowledged by ${opts.user}: ${JSON.stringify(acked)}`);

  // Cleared in the plant, then Clear, Reset, Start, Hold, Unhold from the page.
  plantFault(opts, 'clear');
  await command(page, name, 'Clear', 'Stopped');
  await command(page, name, 'Reset', 'Idle');
  await command(page, name, 'Start', 'Execute');
  await command(page, name, 'Hold', 'Held');
  check((await pageFetch(page, 'GET', `/api/machines/${name}`)).body.state === 'Held', `the API has ${name} Held`);
  await screenshot(page, opts.screenshots, 'operator-machine-held');
  await command(page, name, 'Unhold', 'Execute');
  check(await stateOf(page, name) === 'Execute', `${name} runs again`);

  // OEE and the Contract Net of an order.
  const oeeRows = await page.$$eval('#oee-table tbody tr', (rows) => rows.map((r) => r.dataset.machine));
  check(oeeRows.some((r) => r.startsWith('line')) && oeeRows.length > 1, `OEE per machine and of the line: ${oeeRows.join(', ')}`);
  await page.waitForSelector('#oee-trend .uplot');
  const orders = await page.$$eval('#negotiation-order option', (o) => o.map((x) => x.value));
  if (orders.length) {
    await page.waitForSelector('#timeline li[data-what]');
    const timeline = await page.$$eval('#timeline li[data-what]', (items) => items.map((li) => li.dataset.what));
    check(timeline.length > 0, `the Contract Net of order ${orders[0]} as a timeline: ${timeline.join(', ')}`);
  } else {
    note('no order yet: the Contract Net timeline is empty');
  }
  await screenshot(page, opts.screenshots, 'operator-page');
  check((await messages(page)).length === 0, `no error shown: ${await messages(page)}`);
  checkNoProblems(page, 'the operator page');
}, extra);
