// The report in a real browser (issue 16: headless Chromium, Debian's package): it loads with no
// console error and no network request, every chart has drawn data, every camera view's sliders
// move the drawn horizon, and the export writes the moved angles. Screenshots go to OUT_DIR for a
// person to look at.
//   node browser_test.mjs REPORT.html [OUT_DIR]
import { chromium } from 'playwright-core';
import path from 'node:path';
import fs from 'node:fs';

const [reportPath, outDir] = process.argv.slice(2);
if (!reportPath) {
  console.error('usage: node browser_test.mjs REPORT.html [OUT_DIR]');
  process.exit(2);
}
const failures = [];
const fail = (message) => failures.push(message);

const browser = await chromium.launch({
  executablePath: process.env.X2CAR_CHROMIUM || '/usr/bin/chromium',
  // No sandbox as root; no background connections (the machine has no network, and a report
  // must need none).
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  page.on('console', (message) => {
    if (message.type() === 'error') fail('console error: ' + message.text());
  });
  page.on('pageerror', (error) => fail('page error: ' + error.message));
  page.on('request', (request) => {
    const url = request.url();
    if (!/^(file|data|blob):/.test(url)) fail('network request: ' + url);
  });
  await page.goto('file://' + path.resolve(reportPath), { waitUntil: 'load' });
  await page.waitForFunction(() => window.x2carReport && window.x2carReport.charts.length > 0,
                             null, { timeout: 20000 });
  // Folded charts draw when opened.
  await page.$$eval('details', (all) => all.forEach((details) => { details.open = true; }));
  await page.waitForTimeout(500);

  const charts = await page.evaluate(() => window.x2carReport.charts.map((chart) => {
    const option = chart.instance.getOption();
    const points = option.series.reduce((sum, series) => sum + (series.data ? series.data.length : 0), 0);
    const canvas = chart.element.querySelector('canvas');
    let painted = 0;
    if (canvas && canvas.width > 0 && canvas.height > 0) {
      const pixels = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
      for (let i = 3; i < pixels.length; i += 4) if (pixels[i] > 0) ++painted;
    }
    return { title: chart.title, points: points, painted: painted };
  }));
  if (charts.length === 0) fail('no chart in the report');
  for (const chart of charts) {
    if (chart.points === 0) fail('chart "' + chart.title + '" has no data');
    if (chart.painted < 500) fail('chart "' + chart.title + '" drew almost nothing (' + chart.painted + ' px)');
  }
  console.log('charts: ' + charts.length + ' (' + charts.map((c) => c.title + ': ' + c.points).join('; ') + ')');

  const views = await page.evaluate(() => window.x2carReport.cameraViews.map((view) => view.sensor));
  for (let index = 0; index < views.length; ++index) {
    const sensor = views[index];
    const section = page.locator('#sensor-' + sensor);
    const canvas = section.locator('canvas.adjust-canvas');
    await canvas.scrollIntoViewIfNeeded();
    const horizon = async () => (await canvas.getAttribute('data-horizon')).split(',').map(Number);
    const before = await horizon();
    if (before.length !== 4 || before.some((v) => !Number.isFinite(v))) {
      fail(sensor + ': no horizon drawn (' + before + ')');
      continue;
    }
    const guides = async () => Number(await canvas.getAttribute('data-guide-points'));
    if (!(await guides() > 0)) fail(sensor + ': no lane guide drawn');
    const roll = section.locator('input[data-angle="roll"]');
    const start = Number(await roll.inputValue());
    // The same view for a camera that looks back (yaw turned by 180 deg): its guides run behind the
    // car (none were drawn for one).
    await page.evaluate((index) => { window.x2carReport.cameraViews[index].angles.yaw += 180; }, index);
    await roll.fill(String(start + 0.5));
    if (!(await guides() > 0)) fail(sensor + ': no lane guide drawn for a camera that looks back');
    await page.evaluate((index) => { window.x2carReport.cameraViews[index].angles.yaw -= 180; }, index);
    await roll.fill(String(start));
    await roll.fill(String(start + 2));
    const rolled = await horizon();
    // Rolling the camera tilts its horizon: the two ends move apart vertically.
    const slope = (h) => (h[3] - h[1]) / (h[2] - h[0]);
    if (Math.abs(slope(rolled) - slope(before)) < 0.01) {
      fail(sensor + ': the roll slider did not tilt the horizon (' + before + ' -> ' + rolled + ')');
    }
    const pitch = section.locator('input[data-angle="pitch"]');
    await pitch.fill(String(Number(await pitch.inputValue()) + 1));
    const pitched = await horizon();
    if (Math.abs((pitched[1] + pitched[3]) - (rolled[1] + rolled[3])) < 2) {
      fail(sensor + ': the pitch slider did not move the horizon (' + rolled + ' -> ' + pitched + ')');
    }
    await section.getByRole('button', { name: 'export YAML' }).click();
    const yaml = await section.locator('textarea.export-text').inputValue();
    const exported = Number((yaml.match(/roll: (\S+)/) || [])[1]);
    if (!(Math.abs(exported * 180 / Math.PI - (start + 2)) < 1e-6)) {
      fail(sensor + ': the exported roll ' + exported + ' rad is not the slider\'s ' + (start + 2) + ' deg');
    }
    console.log(sensor + ': horizon ' + before.map((v) => v.toFixed(1)) + ' -> ' +
                pitched.map((v) => v.toFixed(1)) + ' after roll +2, pitch +1 deg');
    if (outDir) await canvas.screenshot({ path: path.join(outDir, 'camera-view-' + sensor + '.png') });
  }
  if (outDir) {
    fs.mkdirSync(outDir, { recursive: true });
    await page.screenshot({ path: path.join(outDir, 'report.png'), fullPage: true });
  }
} finally {
  await browser.close();
}
if (failures.length) {
  for (const message of failures) console.error('FAIL: ' + message);
  process.exit(1);
}
console.log('report ok: ' + reportPath);
