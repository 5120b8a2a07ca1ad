#!/usr/bin/env python3
"""How the hiders handle the props in the prep phase of recorded HideAndSeek episodes.

Usage: scripts/prop_handling.py RECORDING.json
(RECORDING from `rlt eval RUN --record RECORDING.json ...`, or `--policy Hider=scripted`.)

Reads the recording's grab, lock and unlock events and the props' poses up to the prep_end
event of each episode and prints, averaged over the episodes:
- grabs, locks and unlocks per episode, and how many locks were within 0.8 m of an open opening;
- the share of prop-frames each prop spent held, free and locked, and the metres it moved in each;
- per prop paired with an opening (the first n props at level n, each with the open opening
  nearest its start): the straight way from its start to that opening, the path it took, and
  where it ended, for episodes with a fort (every opening closed) and without; and, over the
  frames in which such a prop was held, how often the panel was between the drone and that
  opening (the panel goes first) and how often it moved towards the opening rather than away;
- the holds (from a grab to the lock or release that lets the prop go, or to the prep phase's
  end): how many ended in the frame they began (grabbed and locked in one decision, so the
  prop was never carried), how many lasted LONG_HOLD seconds or more, and how far those took a
  paired prop towards its opening (median);
- what became of the locks made away from every open opening: unlocked again by the drone that
  locked them within REGRIP seconds (a re-grip: with a latched grab, the lock is a hider's only
  way to let go), unlocked by another drone, unlocked later, or still locked at the prep phase's
  end;
- per paired prop, by its place among the props (with prop_pairing prop k is the k-th hider's
  own), the share of episodes in which it ended the prep phase locked near its opening;
- what the closed openings bought in the test phase: by how many openings were closed at the end
  of the prep phase, the episodes, the share in which a hider was tagged and the hidden fraction.
Distances are horizontal (x, z), in metres.
"""
import json
import statistics
import sys
from collections import Counter

NEAR_OPENING = 0.8  # m: a lock this close to an open opening's centre counts as "at a doorway"
STILL = 0.002  # m: a prop that moved less than this in a frame did not move
LONG_HOLD = 0.5  # s: a hold at least this long carried the prop somewhere
REGRIP = 0.5  # s: a lock undone by its own drone within this long was a re-grip


def horizontal(a, b):
    return ((a[0] - b[0]) ** 2 + (a[2] - b[2]) ** 2) ** 0.5


def count_carried(carried, drone, before, after, opening):
    """one held frame of a prop paired with the opening centred at `opening`"""
    carried["frames"] += 1
    # the panel goes first when drone -> panel points the way panel -> opening does
    ahead = (after[0] - drone[0]) * (opening[0] - after[0]) + (after[2] - drone[2]) * (opening[2] - after[2])
    carried["panel_first"] += ahead > 0
    closer = horizontal(after, opening) - horizontal(before, opening)
    if abs(closer) >= STILL:
        carried["moved"] += 1
        carried["towards"] += closer < 0


def prep_frames(episode):
    """the frames up to and including the one holding the prep_end event"""
    for index, frame in enumerate(episode["frames"]):
        if any(e["type"] == "prep_end" for e in frame.get("events", [])):
            return episode["frames"][: index + 1]
    return episode["frames"]


def load_episodes(path):
    try:
        with open(path) as f:
            recording = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"prop_handling.py: cannot read {path}: {e}")
    if not isinstance(recording, dict) or recording.get("format") != "rlt-recording":
        sys.exit(f"prop_handling.py: {path} is not an rlt recording (rlt eval --record)")
    episodes = [e for e in recording.get("episodes", []) if e.get("env") == "HideAndSeek"]
    if not episodes:
        sys.exit(f"prop_handling.py: {path} holds no HideAndSeek episode")
    return episodes


def main(path):
    episodes = load_episodes(path)
    events = Counter()
    locks_near = 0
    metres = Counter()  # state -> metres moved
    frames_in = Counter()  # state -> prop-frames
    ways = {True: [], False: []}  # fort -> (straight, path, end) per prop
    carried = Counter()  # held frames of paired props: "frames", "panel_first", "moved", "towards"
    by_closed = {}  # openings closed at the end of the prep phase -> [(tagged, hidden fraction)]
    locked_at_opening = Counter()  # k -> episodes in which paired prop k ended locked near its opening
    holds = []  # (frames held, metres gained towards its opening or None for an unpaired prop)
    away_locks = Counter()  # what became of a lock away from every open opening -> count
    for episode in episodes:
        # pose row of each dynamic body, and of each prop's
        body_row = {body: row for row, body in enumerate(episode["dynamic_bodies"])}
        rows = {body: row for body, row in body_row.items() if episode["bodies"][body]["kind"] == "prop"}
        openings = [o for o in episode["openings"] if o["open"]]
        frames = prep_frames(episode)
        paired = {  # prop -> the centre of the open opening nearest its start
            p: min((o["centre"] for o in openings), key=lambda c: horizontal(frames[0]["poses"][rows[p]], c))
            for p in sorted(rows)[: len(openings)]
        }
        state = {p: "free" for p in rows}
        holder = {}  # prop -> pose row of the drone that holds it
        travelled = Counter()  # prop -> metres
        hold_start = {}  # prop -> (frame index, pose) of the grab that holds it now
        locked_away = {}  # prop -> (frame index, locking body) of its lock away from every opening
        regrip_frames = REGRIP * episode.get("frame_rate", 50)

        def end_hold(prop, index, pose):
            start, start_pose = hold_start.pop(prop)
            gain = None
            if prop in paired:
                gain = horizontal(start_pose, paired[prop]) - horizontal(pose, paired[prop])
            holds.append((index - start, gain))

        for index, frame in enumerate(frames):
            poses = frame["poses"]
            if index > 0:
                before = frames[index - 1]["poses"]
                for p, row in rows.items():
                    step = horizontal(before[row], poses[row])
                    metres[state[p]] += step
                    frames_in[state[p]] += 1
                    travelled[p] += step
                    if state[p] == "held" and p in paired and p in holder:
                        count_carried(carried, poses[holder[p]], before[row], poses[row], paired[p])
            for e in frame.get("events", []):
                kind, prop = e["type"], e["other"]
                if kind not in ("grab", "lock", "unlock", "release"):
                    continue
                events[kind] += 1
                state[prop] = {"grab": "held", "lock": "locked"}.get(kind, "free")
                if kind == "grab":
                    holder[prop] = body_row[e["body"]]
                    hold_start[prop] = (index, poses[rows[prop]])
                elif prop in hold_start:
                    end_hold(prop, index, poses[rows[prop]])
                if kind == "lock":
                    at = poses[rows[prop]]
                    if any(horizontal(at, o["centre"]) < NEAR_OPENING for o in openings):
                        locks_near += 1
                    else:
                        locked_away[prop] = (index, e["body"])
                elif kind == "unlock" and prop in locked_away:
                    locked_at, locker = locked_away.pop(prop)
                    if e["body"] != locker:
                        away_locks["unlocked by another drone"] += 1
                    elif index - locked_at <= regrip_frames:
                        away_locks["re-gripped"] += 1
                    else:
                        away_locks["unlocked later"] += 1
        away_locks["still locked"] += len(locked_away)
        for prop in list(hold_start):
            end_hold(prop, len(frames) - 1, frames[-1]["poses"][rows[prop]])
        metrics = episode["metrics"]
        fort = metrics.get("fort_rate", 0) == 1
        closed = int(round(metrics.get("openings_closed", 0)))
        by_closed.setdefault(closed, []).append((metrics.get("tag_rate", 0), metrics.get("hidden_fraction", 0)))
        for k, (p, centre) in enumerate(sorted(paired.items())):
            start, end = frames[0]["poses"][rows[p]], frames[-1]["poses"][rows[p]]
            ways[fort].append((horizontal(start, centre), travelled[p], horizontal(end, centre)))
            locked_at_opening[k] += state[p] == "locked" and horizontal(end, centre) < NEAR_OPENING

    n = len(episodes)
    print(f"{n} episodes, per episode in the prep phase:")
    print("  " + ", ".join(f"{k} {events[k] / n:.1f}" for k in ("grab", "lock", "unlock", "release")))
    print(f"  locks within {NEAR_OPENING} m of an open opening: {locks_near} of {events['lock']}")
    away = sum(away_locks.values())
    if away:
        print(
            f"  of the {away} locks away from the openings: re-gripped (unlocked by the same drone within "
            f"{REGRIP} s) {away_locks['re-gripped'] / away:.2f}, unlocked by another drone "
            f"{away_locks['unlocked by another drone'] / away:.2f}, unlocked later "
            f"{away_locks['unlocked later'] / away:.2f}, still locked {away_locks['still locked'] / away:.2f}"
        )
    total = sum(frames_in.values()) or 1
    for s in ("held", "free", "locked"):
        print(f"  {s}: {frames_in[s] / total:.2f} of the prop-frames, moved {metres[s] / n:.2f} m")
    for fort in (True, False):
        props = ways[fort]
        if not props:
            continue
        median = lambda k: statistics.median(r[k] for r in props)
        ratio = statistics.median(r[1] / r[0] for r in props if r[0] > 0)
        label = "with a fort" if fort else "without"
        print(
            f"  props {label} ({len(props)}): start to opening {median(0):.2f} m, path {median(1):.2f} m "
            f"({ratio:.2f} x the straight way), end to opening {median(2):.2f} m (medians)"
        )
    if carried["frames"]:
        print(
            f"  while held: the panel between the drone and its opening in "
            f"{carried['panel_first'] / carried['frames']:.2f} of the frames; moving towards the "
            f"opening in {carried['towards'] / max(1, carried['moved']):.2f} of those it moved in"
        )
    if holds:
        frame_rate = episodes[0].get("frame_rate", 50)
        at_once = sum(1 for frames_held, _ in holds if frames_held == 0)
        long = [gain for frames_held, gain in holds if frames_held >= LONG_HOLD * frame_rate]
        gains = [gain for gain in long if gain is not None]
        line = (
            f"  holds: {len(holds) / n:.1f} per episode; let go in the frame they began (grabbed and "
            f"locked at once) {at_once / len(holds):.2f}, held {LONG_HOLD} s or more {len(long) / len(holds):.2f}"
        )
        if gains:
            line += f", which took their prop {statistics.median(gains):.2f} m towards its opening (median)"
        print(line)
    if locked_at_opening:
        shares = ", ".join(f"prop {k} in {locked_at_opening[k] / n:.2f}" for k in sorted(locked_at_opening))
        print(f"  locked within {NEAR_OPENING} m of its opening when the prep phase ended: {shares} of the episodes")
    print("by openings closed at the end of the prep phase:")
    for closed, outcomes in sorted(by_closed.items()):
        tagged = sum(t for t, _ in outcomes) / len(outcomes)
        hidden = statistics.mean(h for _, h in outcomes)
        print(f"  {closed} closed: {len(outcomes)} episodes, tagged in {tagged:.2f}, hidden fraction {hidden:.2f}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
