// The replay viewer: draws a recorded episode (replay_state.js) with three.js and plays it on a
// timeline. `rlt replay FILE` serves this page with the recording at recording.json.
// window.rltViewer lets tests and the browser console drive and inspect it.
import * as THREE from 'three';
import {OrbitControls} from 'three/addons/OrbitControls.js';

import {EpisodeState, parseRecording} from './replay_state.js';

const COLOURS = {
  floor: 0xd9d4c7,
  wall: 0x9aa3ad,
  obstacle: 0x6f747a,
  prop: 0xe0a040,
  propLocked: 0x7a3b12,
  hider: 0x2f7de1,
  seeker: 0xe0403a,
  opening: 0xf2d43d,
  openingClosed: 0x3ec46d,
  hold: 0xffffff,
};

const ui = Object.fromEntries([
  'scene', 'episode', 'phase', 'clock', 'rewards', 'openings', 'events', 'message', 'play',
  'timeline', 'frame', 'speed', 'cones', 'sight'
].map((id) => [id, document.getElementById(id)]));

const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(window.devicePixelRatio);
ui.scene.appendChild(renderer.domElement);
const camera = new THREE.PerspectiveCamera(50, 1, 0.1, 200);
const controls = new OrbitControls(camera, renderer.domElement);
let scene = null;
let state = null;  // EpisodeState of the episode shown
let drawn = null;  // what is drawn for it (see buildScene)
let frame = 0;     // current frame, fractional while playing
let playing = false;
let lastTime = null;

function showMessage(text) {
  ui.message.textContent = text;
  ui.message.hidden = false;
}

function resize() {
  const w = ui.scene.clientWidth, h = ui.scene.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}

function setPose(object, pose) {
  object.position.set(pose[0], pose[1], pose[2]);
  object.quaternion.set(pose[3], pose[4], pose[5], pose[6]);
}

// the vision cone: apex at the drone, opening along its local +z axis with the drone's field of
// view. Drawn CONE_LENGTH long: the sight range (20 m by default, with a 135-degree cone) would
// cover the arena; the panel states the range.
const CONE_LENGTH = 2.5;
function visionCone(vision, colour) {
  const material = new THREE.MeshBasicMaterial(
      {color: colour, transparent: true, opacity: 0.22, depthWrite: false, side: THREE.DoubleSide});
  const length = Math.min(vision.range, CONE_LENGTH);
  if (vision.cone_degrees >= 180)
    return new THREE.Mesh(new THREE.SphereGeometry(length, 24, 16), material);
  const radius = length * Math.tan((vision.cone_degrees / 2) * Math.PI / 180);
  const geometry = new THREE.ConeGeometry(radius, length, 32, 1, true);
  geometry.rotateX(-Math.PI / 2);        // apex from +y to -z, base towards +z
  geometry.translate(0, 0, length / 2);  // apex at the origin
  return new THREE.Mesh(geometry, material);
}

function buildScene(episode) {
  scene = new THREE.Scene();
  scene.background = new THREE.Color(0x1d2126);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.4);
  sun.position.set(8, 20, 6);
  scene.add(sun);

  state = new EpisodeState(episode);
  drawn = {bodies: [], cones: [], locks: new Map(), holds: new Map(), openings: []};
  let top = 0;
  state.bodies.forEach((b, i) => {
    const pose = b.pose || [0, -100, 0, 0, 0, 0, 1];
    const geometry = b.shape === 'sphere' ? new THREE.SphereGeometry(b.size[0] / 2, 24, 16) :
                                            new THREE.BoxGeometry(b.size[0], b.size[1], b.size[2]);
    let colour = COLOURS[b.kind] ?? COLOURS.wall;
    const slab = b.kind === 'wall' && b.size[1] < 0.5 && b.size[0] > 4 && b.size[2] > 4;
    const material = new THREE.MeshStandardMaterial({color: colour, roughness: 0.8});
    if (b.kind === 'wall' && !slab)
      Object.assign(material, {transparent: true, opacity: 0.45, depthWrite: false});
    if (slab) material.color.setHex(COLOURS.floor);
    const mesh = new THREE.Mesh(geometry, material);
    setPose(mesh, pose);
    // the ceiling would hide the room from above: only the floor slab is drawn
    if (slab && pose[1] > 1) mesh.visible = false;
    if (b.kind === 'wall') top = Math.max(top, pose[1] + b.size[1] / 2);
    scene.add(mesh);
    drawn.bodies.push(mesh);
    if (b.kind === 'hider' || b.kind === 'seeker') {
      const nose = new THREE.Mesh(
          new THREE.ConeGeometry(b.size[0] * 0.25, b.size[0] * 0.5, 12),
          new THREE.MeshStandardMaterial({color: 0xffffff}));
      nose.geometry.rotateX(Math.PI / 2);
      nose.position.z = b.size[0] * 0.6;
      mesh.add(nose);
      if (b.vision) {
        ui.sight.textContent = `vision: ${b.vision.cone_degrees}\u00b0 cone, ${b.vision.range} m ` +
            `(cones drawn ${Math.min(b.vision.range, CONE_LENGTH)} m long)`;
        const cone = visionCone(b.vision, COLOURS[b.kind]);
        mesh.add(cone);
        drawn.cones.push(cone);
      }
    }
    if (b.kind === 'prop') {
      const edges = new THREE.LineSegments(
          new THREE.EdgesGeometry(geometry), new THREE.LineBasicMaterial({color: 0xff3b1f}));
      edges.scale.setScalar(1.02);
      mesh.add(edges);
      drawn.locks.set(i, edges);
      const line = new THREE.Line(
          new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
          new THREE.LineBasicMaterial({color: COLOURS.hold}));
      scene.add(line);
      drawn.holds.set(i, line);
    }
  });
  // the openings: an outline in the wall's plane, yellow until first closed, then green
  state.openings.forEach((o) => {
    if (!o.open) {
      drawn.openings.push(null);
      return;
    }
    const n = new THREE.Vector3(...o.normal), up = new THREE.Vector3(0, 1, 0);
    const right = new THREE.Vector3().crossVectors(up, n).normalize();
    const c = new THREE.Vector3(...o.centre).addScaledVector(n, 0.12);
    const corner = (sx, sy) =>
        c.clone().addScaledVector(right, sx * o.width / 2).addScaledVector(up, sy * o.height / 2);
    const outline = new THREE.LineLoop(
        new THREE.BufferGeometry().setFromPoints(
            [corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)]),
        new THREE.LineBasicMaterial({color: COLOURS.opening}));
    scene.add(outline);
    drawn.openings.push(outline);
  });
  camera.position.set(0, top * 3 + 10, top * 2.6 + 14);
  controls.target.set(0, 0, 0);
  controls.update();
  ui.timeline.max = String(state.frameCount - 1);
  setFrame(0);
}

function setFrame(f) {
  frame = state.clampFrame(f);
  const shown = Math.round(frame);
  state.bodies.forEach((b, i) => {
    if (state.dynamicSlot[i] < 0) return;
    const pose = state.poseAt(shown, i);
    drawn.bodies[i].visible = pose !== null;
    if (pose) setPose(drawn.bodies[i], pose);
  });
  for (const [prop, edges] of drawn.locks) {
    const locked = state.isLocked(shown, prop);
    edges.visible = locked;
    drawn.bodies[prop].material.color.setHex(locked ? COLOURS.propLocked : COLOURS.prop);
    const holder = state.holderOf(shown, prop);
    const line = drawn.holds.get(prop);
    line.visible = holder >= 0;
    if (holder >= 0) {
      line.geometry.setFromPoints([drawn.bodies[holder].position, drawn.bodies[prop].position]);
    }
  }
  drawn.openings.forEach((outline, o) => {
    if (!outline) return;
    const closed = state.openingClosedFrame[o] >= 0 && shown >= state.openingClosedFrame[o];
    outline.material.color.setHex(closed ? COLOURS.openingClosed : COLOURS.opening);
  });
  for (const cone of drawn.cones) cone.visible = ui.cones.checked;
  updatePanel(shown);
}

function updatePanel(shown) {
  const phase = state.phaseAt(shown);
  ui.phase.textContent = phase === 'seeking' ? 'seeking' : 'preparation (seekers frozen)';
  ui.phase.className = `phase ${phase}`;
  ui.clock.textContent = `t = ${(shown / state.frameRate).toFixed(2)} s`;
  ui.frame.textContent = `${shown} / ${state.frameCount - 1}`;
  ui.timeline.value = String(shown);
  const body = ui.rewards.tBodies[0];
  body.replaceChildren(...state.rewardsAt(shown).map((r) => {
    const row = document.createElement('tr');
    if (state.poseAt(shown, r.body) === null) row.className = 'tagged';
    row.innerHTML = `<td style="color:#${COLOURS[r.kind].toString(16).padStart(6, '0')}">${
                        r.kind} ${r.agent}</td>` +
        `<td>${r.own.toFixed(3)}</td><td>${r.group.toFixed(3)}</td>`;
    return row;
  }));
  ui.openings.textContent =
      state.openings
          .map((o, i) => {
            if (!o.open) return null;
            const at = state.openingClosedFrame[i];
            return `${o.kind} ${i}: ` +
                (at >= 0 && shown >= at ? `closed at ${(at / state.frameRate).toFixed(1)} s` :
                                          'open');
          })
          .filter(Boolean)
          .join(' · ');
  ui.events.replaceChildren(...state.eventsUpTo(shown, 6).map((ev) => {
    const item = document.createElement('li');
    item.textContent = `${(ev.frame / state.frameRate).toFixed(1)} s: ${state.describe(ev)}`;
    return item;
  }));
}

function setPlaying(on) {
  playing = on;
  if (on && Math.round(frame) >= state.frameCount - 1) setFrame(0);
  ui.play.innerHTML = on ? '&#10074;&#10074;' : '&#9654;';
  lastTime = null;
}

function animate(time) {
  requestAnimationFrame(animate);
  if (!state) return;
  if (playing && lastTime !== null) {
    const next = frame + ((time - lastTime) / 1000) * state.frameRate * Number(ui.speed.value);
    setFrame(next);
    frame = Math.min(next, state.frameCount - 1);
    if (frame >= state.frameCount - 1) setPlaying(false);
  }
  lastTime = time;
  controls.update();
  renderer.render(scene, camera);
}

// the picture as drawn: how many colours, and a hash of its pixels
function pixels() {
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const data = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, data);
  const colours = new Set();
  let hash = 2166136261;
  for (let i = 0; i < data.length; i += 4) {
    const rgb = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    colours.add(rgb);
    hash = Math.imul(hash ^ rgb, 16777619) >>> 0;
  }
  return {width: w, height: h, distinctColours: colours.size, hash};
}

async function start() {
  resize();
  window.addEventListener('resize', resize);
  const source = new URLSearchParams(location.search).get('file') || 'recording.json';
  let recording;
  try {
    const response = await fetch(source);
    if (!response.ok) throw new Error(`${source}: HTTP ${response.status}`);
    recording = parseRecording(await response.json());
  } catch (error) {
    showMessage(`Cannot play ${source}: ${error.message}`);
    window.rltViewer = {ready: false, error: error.message};
    return;
  }
  recording.episodes.forEach((e, i) => {
    const option = document.createElement('option');
    option.value = String(i);
    option.textContent = `episode ${i + 1} of ${recording.episodes.length} (${e.env})`;
    ui.episode.appendChild(option);
  });
  ui.episode.addEventListener('change', () => {
    setPlaying(false);
    buildScene(recording.episodes[Number(ui.episode.value)]);
  });
  ui.timeline.addEventListener('input', () => {
    setPlaying(false);
    setFrame(Number(ui.timeline.value));
  });
  ui.play.addEventListener('click', () => setPlaying(!playing));
  ui.cones.addEventListener('change', () => setFrame(frame));
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLSelectElement) return;
    if (e.code === 'Space') {
      e.preventDefault();
      setPlaying(!playing);
    }
    if (e.code === 'ArrowRight') {
      setPlaying(false);
      setFrame(Math.round(frame) + 3);
    }
    if (e.code === 'ArrowLeft') {
      setPlaying(false);
      setFrame(Math.round(frame) - 3);
    }
  });
  buildScene(recording.episodes[0]);
  requestAnimationFrame(animate);
  window.rltViewer = {
    ready: true,
    episodeCount: recording.episodes.length,
    get frameCount() {
      return state.frameCount;
    },
    get frame() {
      return Math.round(frame);
    },
    setFrame: (f) => {
      setPlaying(false);
      setFrame(f);
      renderer.render(scene, camera);
    },
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    isPlaying: () => playing,
    pixels,
    // what is drawn at the current frame
    drawn: () => ({
      phase: state.phaseAt(Math.round(frame)),
      drones: state.bodies.map((b, i) => ({b, i}))
                  .filter(({b}) => b.agent_id >= 0)
                  .map(({b, i}) => ({
                         body: i,
                         kind: b.kind,
                         visible: drawn.bodies[i].visible,
                         position: drawn.bodies[i].position.toArray()
                       })),
      lockedProps: [...drawn.locks].filter(([, edges]) => edges.visible).map(([prop]) => prop),
      cones: drawn.cones.filter((c) => c.visible).length,
      rewards: [...ui.rewards.tBodies[0].rows].map((r) => [...r.cells].map((c) => c.textContent)),
    }),
  };
}

start();
