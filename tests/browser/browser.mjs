// What the browser scenarios share: headless Chromium (Debian's, /usr/bin/chromium) driven by
// puppeteer-core, a fresh browser context per user (its own cookies), logging in through the
// page's form, waiting for conditions (never for fixed times), screenshots, and the failures a
// page must not have: uncaught errors and Content-Security-Policy refusals (an inline script or
// style, eval, a resource from elsewhere).
import {parseArgs} from 'node:util';
import {mkdirSync} from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

export const WAIT_MS = 120000;

export function options(extra = {}) {
  const {values} = parseArgs({
    options: {
      url: {type: 'string'},
      user: {type: 'string'},
      password: {type: 'string'},
      screenshots: {type: 'string', default: 'browser-screenshots'},
      chromium: {type: 'string', default: process.env.SF_CHROMIUM || '/usr/bin/chromium'},
      ...extra,
    },
  });
  if (!values.url) fail('--url of the dashboard is required');
  return values;
}

export function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}

export function check(condition, message) {
  if (!condition) fail(message);
  console.log(`ok: ${message}`);
}

export function note(message) {
  console.log(`note: ${message}`);
}

export async function launch(opts) {
  return puppeteer.launch({
    executablePath: opts.chromium,
    headless: true,
    // The test runs as root in a container: Chromium's sandbox needs user namespaces it may not have.
    args: ['--no-sandbox', '--disable-dev-shm-usage', '--no-first-run'],
    // Chromium's start takes longer than puppeteer's 30 s default on a loaded 2-core machine.
    timeout: WAIT_MS,
  });
}

// A page in a context of its own, with the problems the page reports collected in page.problems.
export async function newPage(browser, {width = 1280, height = 900, mobile = false} = {}) {
  const context = await browser.createBrowserContext();
  const page = await context.newPage();
  await page.setViewport({width, height, isMobile: mobile, hasTouch: mobile, deviceScaleFactor: mobile ? 2 : 1});
  page.setDefaultTimeout(WAIT_MS);
  page.problems = [];
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  page.on('console', (message) => {
    const text = message.text();
    if (message.type() === 'error' && /Content Security Policy|Refused to/i.test(text)) page.problems.push(`CSP: ${text}`);
  });
  return page;
}

// Keeps every WebSocket the page opens in window.sfSockets, so a scenario can cut the live
// stream as a network would (before the page's scripts run; not subject to its CSP).
export async function recordSockets(page) {
  await page.evaluateOnNewDocument(() => {
    const Native = window.WebSocket;
    window.sfSockets = [];
    window.WebSocket = class extends Native {
      constructor(...args) {
        super(...args);
        window.sfSockets.push(this);
      }
    };
  });
}

// Closes the page's open live stream; resolves once the page has opened it again.
export async function cutLiveStream(page) {
  const opens = Number(await page.$eval('#live', (e) => e.dataset.opens));
  await page.evaluate(() => window.sfSockets.filter((s) => s.readyState === WebSocket.OPEN).forEach((s) => s.close()));
  await page.waitForFunction((n) => Number(document.querySelector('#live').dataset.opens) > n, {}, opens);
  note(`live stream cut and opened again (${opens + 1} opens)`);
}

// Fails on any uncaught error or CSP refusal the page had.
export function checkNoProblems(page, what) {
  check(page.problems.length === 0, `${what} ran without uncaught errors or CSP refusals: ${page.problems.join('; ')}`);
}

export async function open(page, url) {
  const response = await page.goto(url, {waitUntil: 'load'});
  check(response && response.ok(), `${url} loads (${response && response.status()})`);
  return response;
}

// Logs in with the page's form; resolves once the header names the user.
export async function login(page, user, password) {
  await page.waitForSelector('#login:not([hidden])');
  await page.type('#login input[name=user]', user);
  await page.type('#login input[name=password]', password);
  await page.click('#login button[type=submit]');
  await page.waitForFunction((u) => document.querySelector('#who').textContent.startsWith(u), {}, user);
}

export async function waitLive(page) {
  await page.waitForSelector('#live[data-connected=true]');
}

export async function screenshot(page, dir, name) {
  mkdirSync(dir, {recursive: true});
  const file = path.join(dir, `${name}.png`);
  await page.screenshot({path: file, fullPage: true});
  note(`screenshot ${file}`);
}

// The texts of the error messages the page shows.
export async function messages(page, kind = 'error') {
  return page.$$eval(`#messages .message.${kind} span`, (nodes) => nodes.map((n) => n.textContent));
}

// A request from inside the page (its cookie, the CSRF token of its session unless csrf is false):
// {status, body}.
export async function pageFetch(page, method, url, {body, csrf = true} = {}) {
  return page.evaluate(async (method, url, body, csrf) => {
    const headers = {Accept: 'application/json'};
    if (csrf) {
      const session = await (await fetch('/api/session', {credentials: 'same-origin'})).json();
      headers['X-CSRF-Token'] = session.csrf;
    }
    if (body !== undefined) headers['Content-Type'] = 'application/json';
    const response = await fetch(url, {method, headers, credentials: 'same-origin',
      body: body === undefined ? undefined : JSON.stringify(body)});
    const text = await response.text();
    let parsed = text;
    try { parsed = JSON.parse(text); } catch { /* kept as text */ }
    return {status: response.status, body: parsed};
  }, method, url, body, csrf);
}

// What every page showed when a scenario stopped, and the messages on it.
async function failureScreenshots(browser, opts) {
  const name = path.basename(process.argv[1], '.mjs');
  let i = 0;
  for (const context of browser.browserContexts()) {
    for (const page of await context.pages()) {
      try {
        await screenshot(page, opts.screenshots, `failed-${name}-${++i}`);
        console.error(`page ${page.url()} shows: ${JSON.stringify(await messages(page))}`);
      } catch (e) {
        console.error(`no screenshot of ${page.url()}: ${e.message}`);
      }
    }
  }
}

// Runs a scenario, closing the browser however it ends.
export async function scenario(fn, extra) {
  const opts = options(extra);
  const browser = await launch(opts);
  try {
    await fn(browser, opts);
  } catch (e) {
    console.error(e && e.stack ? e.stack : e);
    await failureScreenshots(browser, opts);
    fail(`scenario stopped: ${e && e.message}`);
  } finally {
    await browser.close();
  }
}
