// The replay viewer end to end: an episode recorded by `rlt eval --record`, served by `rlt replay`,
// loaded in headless Chromium (Debian's, driven by playwright-core from npm). Checks what is drawn
// against the recording itself: the frame count, a picture that is not blank, the drones where
// the recording puts them, the locked prop, the phase, the rewards so far; scrubbing and playing
// change the picture; nothing is fetched from outside localhost. Also replay_state.js alone in Node
// and the errors of `rlt replay`.
//
// Usage: node replay_viewer_test.mjs RLT_BINARY VIEWER_BUILD_DIR (build/viewer: node_modules, site)
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const [rltArgument, viewerArgument] = process.argv.slice(2);
if (!rltArgument || !viewerArgument) throw new Error('usage: node replay_viewer_test.mjs RLT_BINARY VIEWER_BUILD_DIR');
const rlt = path.resolve(rltArgument), viewerBuild = path.resolve(viewerArgument);
const here = path.dirname(fileURLToPath(import.meta.url));
const load = (file) => import(pathToFileURL(file).href);
const { parseRecording, EpisodeState } = await load(path.join(here, '../../viewer/replay_state.js'));
const { chromium } = await load(path.join(viewerBuild, 'node_modules/playwright-core/index.mjs'));

const work = fs.mkdtempSync(path.join(os.tmpdir(), 'replay_viewer_test_'));
after(() => fs.rmSync(work, { recursive: true, force: true }));

// one level-1 episode of 900 frames: the scripted hider locks the prop in the doorway, the
// scripted seekers come out at frame 360
const recordingFile = path.join(work, 'replay.json');
const recorded = spawnSync(rlt, ['eval', '--env', 'HideAndSeek', '--policy', 'Hider=scripted',
  '--policy', 'Seeker=scripted', '--param', 'level=1', '--param', 'episode_frames=900',
  '--episodes', '1', '--num-envs', '1', '--record', recordingFile], { encoding: 'utf8' });
assert.equal(recorded.status, 0, recorded.stderr);
const recording = JSON.parse(fs.readFileSync(recordingFile, 'utf8'));
const episode = recording.episodes[0];

test('replay_state follows the recording', () => {
  const state = new EpisodeState(parseRecording(recording).episodes[0]);
  assert.equal(state.frameCount, episode.frames.length);
  const prepEnd = episode.frames.findIndex((f) => (f.events || []).some((e) => e.type === 'prep_end'));
  assert.ok(prepEnd > 0);
  assert.equal(state.prepEndFrame, prepEnd);
  assert.equal(state.phaseAt(prepEnd - 1), 'preparation');
  assert.equal(state.phaseAt(prepEnd), 'seeking');
  // the final rewards are the sums of the recorded ones
  const last = state.rewardsAt(state.frameCount - 1);
  for (const r of last) {
    const own = episode.frames.reduce((sum, f) => sum + (f.rewards ? f.rewards[r.agent] : 0), 0);
    assert.ok(Math.abs(r.own - own) < 1e-9, `agent ${r.agent}: ${r.own} vs ${own}`);
  }
  assert.ok(last.some((r) => r.kind === 'hider' && r.own > 0.1), 'the hiders were paid for closing');
  // the prop is locked from its lock event on
  const lockFrame = episode.frames.findIndex((f) => (f.events || []).some((e) => e.type === 'lock'));
  const prop = episode.frames[lockFrame].events.find((e) => e.type === 'lock').other;
  assert.equal(state.isLocked(lockFrame - 1, prop), false);
  assert.equal(state.isLocked(lockFrame, prop), true);
});

test('replay_state names what is wrong with a file', () => {
  assert.throws(() => parseRecording({ format: 'other' }), /not an rlt recording/);
  assert.throws(() => parseRecording({ format: 'rlt-recording', version: 99, episodes: [] }), /version 99/);
  assert.throws(() => parseRecording({ format: 'rlt-recording', version: 2, episodes: [] }), /no episodes/);
  assert.throws(() => parseRecording({ format: 'rlt-recording', version: 2, episodes: [{ bodies: [] }] }),
                /episode 0 has no "dynamic_bodies"/);
});

test('rlt replay refuses what it cannot play', () => {
  let r = spawnSync(rlt, ['replay', path.join(work, 'missing.json')], { encoding: 'utf8' });
  assert.equal(r.status, 1);
  assert.match(r.stderr, /cannot read .*missing\.json/);
  const other = path.join(work, 'other.json');
  fs.writeFileSync(other, '{"format":"something else"}');
  r = spawnSync(rlt, ['replay', other], { encoding: 'utf8' });
  assert.equal(r.status, 1);
  assert.match(r.stderr, /is not an rlt recording/);
  r = spawnSync(rlt, ['replay', recordingFile, '--port', '70000'], { encoding: 'utf8' });
  assert.equal(r.status, 2);
  assert.match(r.stderr, /--port/);
});

// starts `rlt replay` on a free port; resolves to [process, address]
function startReplay(file) {
  return new Promise((resolve, reject) => {
    const server = spawn(rlt, ['replay', file, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    server.stdout.on('data', (chunk) => {
      out += chunk;
      const match = out.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (match) resolve([server, match[0]]);
    });
    server.on('exit', (code) => reject(new Error(`rlt replay exited with ${code}: ${out}`)));
    setTimeout(() => reject(new Error(`rlt replay printed no address: ${out}`)), 10000);
  });
}

test('the viewer draws the episode and plays it', { timeout: 120000 }, async () => {
  const [server, address] = await startReplay(recordingFile);
  // the flags that keep Chromium off the network on this machine, a fresh profile, software WebGL
  const browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--enable-unsafe-swiftshader', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update',
           '--disable-sync'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
    const outside = [], errors = [];
    page.on('request', (request) => { if (!request.url().startsWith(address)) outside.push(request.url()); });
    page.on('pageerror', (error) => errors.push(error.message));
    page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
    await page.goto(address);
    await page.waitForFunction(() => window.rltViewer?.ready || window.rltViewer?.error, null, { timeout: 30000 });
    assert.equal(await page.evaluate(() => window.rltViewer.error), undefined);

    const frames = episode.frames.length;
    assert.equal(await page.evaluate(() => window.rltViewer.frameCount), frames);
    assert.equal(await page.textContent('#frame'), `0 / ${frames - 1}`);
    assert.equal(await page.getAttribute('#timeline', 'max'), String(frames - 1));

    // frame 0: a picture with many colours, the preparation phase, nobody paid yet
    const first = await page.evaluate(() => window.rltViewer.pixels());
    assert.ok(first.distinctColours > 50, `a blank picture: ${first.distinctColours} colours`);
    assert.match(await page.textContent('#phase'), /preparation/);
    let drawn = await page.evaluate(() => window.rltViewer.drawn());
    assert.equal(drawn.phase, 'preparation');
    assert.deepEqual(drawn.lockedProps, []);
    assert.equal(drawn.cones, 4, 'a vision cone per drone');

    // scrubbing with the timeline: frame 700 (seeking, the prop locked), a different picture
    await page.locator('#timeline').fill('700');
    assert.equal(await page.textContent('#frame'), `700 / ${frames - 1}`);
    const later = await page.evaluate(() => window.rltViewer.pixels());
    assert.notEqual(later.hash, first.hash, 'scrubbing did not change the picture');
    drawn = await page.evaluate(() => window.rltViewer.drawn());
    assert.equal(drawn.phase, 'seeking');
    assert.match(await page.textContent('#phase'), /seeking/);
    const state = new EpisodeState(episode);
    assert.deepEqual(drawn.lockedProps, state.props.filter((p) => state.isLocked(700, p)));
    assert.equal(drawn.lockedProps.length, 1);
    for (const drone of drawn.drones) {
      const pose = state.poseAt(700, drone.body);
      assert.equal(drone.visible, pose !== null);
      if (pose) for (let k = 0; k < 3; k++) assert.ok(Math.abs(drone.position[k] - pose[k]) < 1e-4, `${drone.kind} ${drone.body}`);
    }
    const rewards = state.rewardsAt(700);
    assert.deepEqual(drawn.rewards, rewards.map((r) => [`${r.kind} ${r.agent}`, r.own.toFixed(3), r.group.toFixed(3)]));
    assert.match(await page.textContent('#openings'), /doorway 0: closed at/);

    // the cones can be hidden
    await page.locator('#cones').uncheck();
    assert.equal((await page.evaluate(() => window.rltViewer.drawn())).cones, 0);
    assert.notEqual((await page.evaluate(() => window.rltViewer.pixels())).hash, later.hash);

    // playing moves the frame on; pausing stops it
    await page.locator('#timeline').fill('100');
    await page.click('#play');
    await page.waitForFunction(() => window.rltViewer.frame > 110, null, { timeout: 10000 });
    await page.click('#play');
    const paused = await page.evaluate(() => window.rltViewer.frame);
    await page.waitForTimeout(300);
    assert.equal(await page.evaluate(() => window.rltViewer.frame), paused);

    assert.deepEqual(outside, [], 'requests outside localhost');
    assert.deepEqual(errors, [], 'errors in the page');

    // a file the server does not have: the page says so
    await page.goto(`${address}?file=missing.json`);
    await page.waitForFunction(() => window.rltViewer && !window.rltViewer.ready, null, { timeout: 30000 });
    assert.match(await page.textContent('#message'), /Cannot play missing\.json: missing\.json: HTTP 404/);
  } finally {
    await browser.close();
    server.kill();
  }
});
