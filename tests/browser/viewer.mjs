// A viewer watches but may not command: the page shows the commands and the acknowledgement
// disabled and says why; a command sent anyway (the button enabled by hand) is refused by the
// server and the page shows the refusal; the API refuses a viewer's command with 403 and the
// machine stays as it was.
import {check, checkNoProblems, login, messages, newPage, open, pageFetch, scenario, screenshot, waitLive} from './browser.mjs';

const extra = {machine: {type: 'string', default: 'conveyor2'}};

await scenario(async (browser, opts) => {
  const name = opts.machine;
  const page = await newPage(browser);
  await open(page, `${opts.url}/operator.html`);
  await login(page, opts.user, opts.password);
  await waitLive(page);
  await page.waitForSelector(`#schematic [data-machine="${name}"][data-state=Execute]`);
  await page.click(`#machines button[data-select="${name}"]`);
  await page.waitForSelector('#machine:not([hidden])[data-state=Execute]');
  const disabled = await page.$$eval('#commands button', (b) => b.map((x) => [x.dataset.command, x.disabled]));
  check(disabled.length > 0 && disabled.every(([, d]) => d), `every command is disabled for a viewer: ${JSON.stringify(disabled)}`);
  check(await page.$eval('#command-note', (n) => !n.hidden && n.textContent.includes('viewer')), 'the page says a viewer may not command');
  const acks = await page.$$eval('#alarm-list button.ack', (b) => b.map((x) => x.disabled));
  check(acks.every((d) => d), `acknowledging is disabled for a viewer (${acks.length} alarms)`);

  // Sent anyway: the server refuses, the page shows it.
  // Enabled and clicked in one go: a live update in between would disable it again.
  await page.$eval('#commands button[data-command=Hold]', (b) => {
    b.disabled = false;
    b.click();
  });
  await page.waitForSelector('#messages .message.error');
  const shown = await messages(page);
  check(shown.some((m) => m.includes('(403)')), `the page shows the server's refusal: ${shown}`);
  await screenshot(page, opts.screenshots, 'viewer-refused');

  // The API refuses it too, with or without the CSRF token, and nothing changed.
  const answer = await pageFetch(page, 'POST', `/api/machines/${name}/commands/Hold`);
  check(answer.status === 403 && typeof answer.body.error === 'string', `the API refuses a viewer's Hold: ${answer.status} ${JSON.stringify(answer.body)}`);
  const noToken = await pageFetch(page, 'POST', `/api/machines/${name}/commands/Hold`, {csrf: false});
  check(noToken.status === 403, `and one without the CSRF token: ${noToken.status}`);
  const machine = (await pageFetch(page, 'GET', `/api/machines/${name}`)).body;
  check(machine.state === 'Execute', `${name} is still in Execute: ${machine.state}`);
  check(await page.$eval(`#schematic [data-machine="${name}"]`, (g) => g.dataset.state) === 'Execute', 'and so on the page');
  checkNoProblems(page, 'the operator page of a viewer');
}, extra);
