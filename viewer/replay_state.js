// What a recorded episode shows at each frame, computed once from the recording
// (docs/recording_format.md): body poses, which props are locked and held, the phase, each
// agent's rewards so far, when each opening was first closed and the events so far. No drawing
// here (viewer.js draws), so Node can test it without a browser.

export const SUPPORTED_VERSIONS = [1, 2];

// Checks the document's outline and returns it; throws an Error that names what is wrong.
export function parseRecording(document) {
  if (document === null || typeof document !== 'object')
    throw new Error('the recording is not a JSON object');
  if (document.format !== 'rlt-recording') {
    throw new Error(
        `not an rlt recording: "format" is ${JSON.stringify(document.format)}, ` +
        'expected "rlt-recording" (write one with rlt eval --record FILE)');
  }
  if (!SUPPORTED_VERSIONS.includes(document.version)) {
    throw new Error(
        `recording version ${document.version} is not one this viewer plays ` +
        `(${SUPPORTED_VERSIONS.join(', ')})`);
  }
  if (!Array.isArray(document.episodes) || document.episodes.length === 0) {
    throw new Error(
        'the recording has no episodes (the env may not record: only the drone envs do)');
  }
  document.episodes.forEach((e, i) => {
    for (const key of ['bodies', 'dynamic_bodies', 'frames']) {
      if (!Array.isArray(e[key])) throw new Error(`episode ${i} has no "${key}" list`);
    }
    if (e.frames.length === 0) throw new Error(`episode ${i} has no frames`);
    if (!(e.frame_rate > 0)) throw new Error(`episode ${i} has no positive "frame_rate"`);
  });
  return document;
}

export class EpisodeState {
  constructor(episode) {
    this.episode = episode;
    this.bodies = episode.bodies;
    this.frameCount = episode.frames.length;
    this.frameRate = episode.frame_rate;
    this.openings = episode.openings || [];
    // body index -> its place in each frame's poses, or -1 for bodies that never move
    this.dynamicSlot = new Int32Array(this.bodies.length).fill(-1);
    episode.dynamic_bodies.forEach((body, slot) => {
      this.dynamicSlot[body] = slot;
    });

    this.agentCount = 1 + Math.max(-1, ...this.bodies.map((b) => b.agent_id));
    this.agentBody = new Int32Array(this.agentCount).fill(-1);  // agent id -> body index
    this.bodies.forEach((b, i) => {
      if (b.agent_id >= 0) this.agentBody[b.agent_id] = i;
    });

    const props = this.bodies.map((b, i) => (b.kind === 'prop' ? i : -1)).filter((i) => i >= 0);
    this.props = props;
    // per prop: locked (1) and holder body (-1 none) at each frame
    this.locked = new Map(props.map((p) => [p, new Uint8Array(this.frameCount)]));
    this.holder = new Map(props.map((p) => [p, new Int32Array(this.frameCount).fill(-1)]));
    // cumulative rewards, [frames][agents]
    this.ownRewards = new Float64Array(this.frameCount * this.agentCount);
    this.groupRewards = new Float64Array(this.frameCount * this.agentCount);
    this.prepEndFrame = -1;
    this.openingClosedFrame = this.openings.map(() => -1);
    this.events = [];  // {frame, type, body, other}, in order

    const lockedNow = new Map(props.map((p) => [p, 0]));
    const holderNow = new Map(props.map((p) => [p, -1]));
    const own = new Float64Array(this.agentCount), group = new Float64Array(this.agentCount);
    episode.frames.forEach((frame, f) => {
      for (const ev of frame.events || []) {
        this.events.push({frame: f, ...ev});
        if (ev.type === 'lock' && lockedNow.has(ev.other)) lockedNow.set(ev.other, 1);
        if (ev.type === 'unlock' && lockedNow.has(ev.other)) lockedNow.set(ev.other, 0);
        if (ev.type === 'grab' && holderNow.has(ev.other)) holderNow.set(ev.other, ev.body);
        if (ev.type === 'release' && holderNow.has(ev.other)) holderNow.set(ev.other, -1);
        if (ev.type === 'prep_end' && this.prepEndFrame < 0) this.prepEndFrame = f;
        if (ev.type === 'closed' && ev.other >= 0 && ev.other < this.openings.length &&
            this.openingClosedFrame[ev.other] < 0) {
          this.openingClosedFrame[ev.other] = f;
        }
      }
      // a tagged hider lets go of what it held
      for (const [prop, hider] of holderNow) {
        if (hider >= 0 && this.dynamicSlot[hider] >= 0 &&
            frame.poses[this.dynamicSlot[hider]] === null) {
          holderNow.set(prop, -1);
        }
      }
      for (const p of props) {
        this.locked.get(p)[f] = lockedNow.get(p);
        this.holder.get(p)[f] = holderNow.get(p);
      }
      (frame.rewards || []).forEach((r, a) => {
        if (a < this.agentCount) own[a] += r;
      });
      (frame.group_rewards || []).forEach((r, a) => {
        if (a < this.agentCount) group[a] += r;
      });
      this.ownRewards.set(own, f * this.agentCount);
      this.groupRewards.set(group, f * this.agentCount);
    });
  }

  clampFrame(f) {
    return Math.min(this.frameCount - 1, Math.max(0, Math.round(f)));
  }

  // [x, y, z, qx, qy, qz, qw] of `body` at frame f, or null when it has left the world
  poseAt(f, body) {
    const slot = this.dynamicSlot[body];
    if (slot < 0) return this.bodies[body].pose;
    return this.episode.frames[this.clampFrame(f)].poses[slot];
  }

  // 'preparation' (seekers frozen) until the prep_end event's frame, then 'seeking'
  phaseAt(f) {
    return this.prepEndFrame >= 0 && this.clampFrame(f) >= this.prepEndFrame ? 'seeking' :
                                                                               'preparation';
  }

  isLocked(f, prop) {
    return this.locked.get(prop)[this.clampFrame(f)] === 1;
  }
  holderOf(f, prop) {
    return this.holder.get(prop)[this.clampFrame(f)];
  }

  // rewards paid up to and including frame f: [{agent, body, kind, own, group}]
  rewardsAt(f) {
    const base = this.clampFrame(f) * this.agentCount;
    const out = [];
    for (let a = 0; a < this.agentCount; a++) {
      const body = this.agentBody[a];
      if (body < 0) continue;
      out.push({
        agent: a,
        body,
        kind: this.bodies[body].kind,
        own: this.ownRewards[base + a],
        group: this.groupRewards[base + a]
      });
    }
    return out;
  }

  // the last `count` events at or before frame f, newest last
  eventsUpTo(f, count) {
    const frame = this.clampFrame(f);
    let end = 0;
    while (end < this.events.length && this.events[end].frame <= frame) end++;
    return this.events.slice(Math.max(0, end - count), end);
  }

  // a sentence for an event, naming bodies by kind and agent
  describe(ev) {
    const name = (i) => {
      if (i < 0 || i >= this.bodies.length) return '';
      const b = this.bodies[i];
      return b.agent_id >= 0 ? `${b.kind} ${b.agent_id}` : `${b.kind} #${i}`;
    };
    switch (ev.type) {
      case 'grab':
        return `${name(ev.body)} grabs ${name(ev.other)}`;
      case 'release':
        return `${name(ev.body)} releases ${name(ev.other)}`;
      case 'lock':
        return `${name(ev.body)} locks ${name(ev.other)}`;
      case 'unlock':
        return `${name(ev.body)} unlocks ${name(ev.other)}`;
      case 'tag':
        return `${name(ev.body)} is tagged`;
      case 'closed': {
        const o = this.openings[ev.other];
        return `${o ? o.kind : 'opening'} ${ev.other} closed`;
      }
      case 'prep_end':
        return 'the seekers are released';
      default:
        return ev.type;
    }
  }
}
