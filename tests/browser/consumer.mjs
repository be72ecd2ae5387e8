// A consumer on a phone-sized screen: logs in, is stopped by the checks of the order form (too
// many candies, a quantity of 0) with nothing sent, places a valid order and follows it through
// the live stream (cut once on the way) until it is done, with its machines and a matching
// inspection.
import {check, checkNoProblems, cutLiveStream, login, newPage, note, open, pageFetch, recordSockets, scenario, screenshot, waitLive}
  from './browser.mjs';

const DONE_MS = 900000;  // a box through the simulated line takes minutes on a loaded machine

async function setLine(page, index, candy, quantity) {
  const row = (await page.$$('#lines .line'))[index];
  await row.$eval('.candy', (select, value) => {
    select.value = value;
    select.dispatchEvent(new Event('change', {bubbles: true}));
  }, candy);
  const input = await row.$('.quantity');
  await input.click({clickCount: 3});
  await input.type(String(quantity));
}

const errors = (page) => page.$$eval('#order-errors li', (items) => items.map((li) => li.textContent));

await scenario(async (browser, opts) => {
  const page = await newPage(browser, {width: 390, height: 844, mobile: true});
  await recordSockets(page);
  const orderGets = [];
  page.on('request', (r) => { if (/\/api\/orders\/[^/?]+$/.test(new URL(r.url()).pathname) && r.method() === 'GET') orderGets.push(r.url()); });
  await open(page, `${opts.url}/index.html`);
  await login(page, opts.user, opts.password);
  await page.waitForSelector('#order:not([hidden]) #box option');
  await waitLive(page);
  const catalog = (await pageFetch(page, 'GET', '/api/catalog')).body;
  const box = catalog.box_types[0];
  const [first, second] = catalog.candy_types.map((c) => c.name);
  const before = (await pageFetch(page, 'GET', '/api/orders')).body.length;

  // The page refuses what the server would: more candies than the box holds, a quantity of 0.
  await page.select('#box', box.name);
  await setLine(page, 0, first, box.capacity + 1);
  await page.waitForFunction(() => document.querySelector('#order-errors li'));
  check((await errors(page)).some((e) => e.includes('do not fit')), `${box.capacity + 1} candies are refused for a ${box.name}: ${await errors(page)}`);
  check(await page.$eval('#place', (b) => b.disabled), 'the order cannot be placed while it is wrong');
  await setLine(page, 0, first, 0);
  await page.waitForFunction(() => document.querySelector('#order-errors li'));
  check((await errors(page)).some((e) => e.includes('1 or more')), `a quantity of 0 is refused: ${await errors(page)}`);
  await page.click('#order button[type=submit]').catch(() => {});
  check((await pageFetch(page, 'GET', '/api/orders')).body.length === before, 'nothing was ordered meanwhile');
  // The page's checks and the server's agree: what the page refuses, the API refuses with 400 and
  // stores nothing; a full box passes the page's checks.
  const cases = [
    {box: box.name, candy: {}},
    {box: box.name, candy: {[first]: 0}},
    {box: box.name, candy: {[first]: -1}},
    {box: box.name, candy: {[first]: 1.5}},
    {box: box.name, candy: {[first]: box.capacity, [second]: 1}},
    {box: box.name, candy: {'no-such-candy': 1}},
    {box: 'no-such-box', candy: {[first]: 1}},
  ];
  const verdicts = await page.evaluate(async (cases, full) => {
    const {checkOrder} = await import('/js/order_check.js');
    const catalog = await (await fetch('/api/catalog')).json();
    const lines = (c) => Object.entries(c.candy).map(([candy, quantity]) => ({candy, quantity}));
    return {refused: cases.map((c) => checkOrder(catalog, c.box, lines(c)).errors),
      full: checkOrder(catalog, full.box, lines(full)).errors};
  }, cases, {box: box.name, candy: {[first]: box.capacity}});
  check(verdicts.full.length === 0, `a full ${box.name} passes the page's checks`);
  for (const [i, c] of cases.entries()) {
    const answer = await pageFetch(page, 'POST', '/api/orders', {body: c});
    check(verdicts.refused[i].length > 0 && answer.status === 400 && typeof answer.body.error === 'string',
      `${JSON.stringify(c)}: the page refuses it (${verdicts.refused[i].join('; ')}) and so does the API ` +
      `(${answer.status} ${JSON.stringify(answer.body)})`);
  }
  check((await pageFetch(page, 'GET', '/api/orders')).body.length === before, 'no refused order was stored');
  const width = await page.evaluate(() => [document.documentElement.scrollWidth, window.innerWidth]);
  check(width[0] <= width[1], `the order form fits the phone's width (${width[0]} of ${width[1]} px)`);
  await screenshot(page, opts.screenshots, 'consumer-order-form-refused');

  // A valid order: two of one candy, one of another.
  await setLine(page, 0, first, 2);
  await page.click('#add-line');
  await setLine(page, 1, second, 1);
  await page.waitForFunction(() => !document.querySelector('#place').disabled);
  await screenshot(page, opts.screenshots, 'consumer-order-form');
  await page.click('#place');
  await page.waitForSelector('#tracking:not([hidden])');
  const id = await page.$eval('#order-id', (e) => e.textContent);
  check(id.length > 0, `the order was placed: ${id}`);
  await page.waitForSelector('#milestones li[data-step=accepted].reached');
  await screenshot(page, opts.screenshots, 'consumer-order-accepted');
  // The stream lost (as on a phone changing networks): the page opens it again, subscribes the
  // order again and goes on following it.
  await cutLiveStream(page);

  // Followed live until done.
  await page.waitForSelector('#tracking[data-state=done], #tracking[data-state=failed], #tracking[data-state=cancelled]',
    {timeout: DONE_MS});
  const state = await page.$eval('#tracking', (e) => e.dataset.state);
  check(state === 'done', `the order ends done on the page: ${state}`);
  const reached = await page.$$eval('#milestones li.reached', (items) => items.map((li) => li.dataset.step));
  for (const step of ['accepted', 'awarded', 'loaded', 'done']) check(reached.includes(step), `the page shows the step ${step}`);
  const machines = await page.$eval('#order-machines', (e) => e.textContent);
  check(machines && machines !== 'none yet', `the page names the machines that made it: ${machines}`);
  // The inspection comes with the order service's LastInspection value, not with its step events:
  // it may follow "done".
  await page.waitForFunction(() => document.querySelector('#order-inspection').dataset.matches);
  const inspection = await page.$eval('#order-inspection', (e) => [e.textContent, e.dataset.matches]);
  check(inspection[1] === 'true', `the inspection matches the order: ${inspection[0]}`);
  const steps = await page.$$eval('#steps li', (items) => items.length);
  const opens = Number(await page.$eval('#live', (e) => e.dataset.opens));
  check(orderGets.length <= opens + 1,
    `the steps (${steps}) came through the live stream: the order was fetched ${orderGets.length} times, the stream opened ${opens} times`);
  const api = (await pageFetch(page, 'GET', `/api/orders/${encodeURIComponent(id)}`)).body;
  check(api.state === 'done' && api.steps.length === steps, `the API has the same order: ${api.state}, ${api.steps.length} steps`);
  const mine = (await pageFetch(page, 'GET', '/api/orders')).body;
  check(mine.length === before + 1 && mine.every((o) => o.owner === opts.user), `the consumer sees their own orders only (${mine.length})`);
  await screenshot(page, opts.screenshots, 'consumer-order-done');
  note(`order ${id}: ${reached.join(' → ')}`);
  checkNoProblems(page, 'the consumer page');
});
