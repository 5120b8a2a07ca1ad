#!/bin/sh
# scripts/prop_handling.py on two episodes of the scripted hider at level 1 (one grab and one lock
# per episode, both locks at the doorway and the prop locked there at the end, both forts built,
# the panel pushed ahead of the drone, one hold per episode carried from about 2 m out to the
# doorway and let go by the lock, both episodes counted with one opening closed),
# on a made-up recording whose hider locks a prop away from the doorway four times (undone by
# itself 6 frames later, by the other hider, by itself 54 frames later, and not at all), and on
# a file that is not a recording.
# Usage: prop_handling_test.sh RLT_BINARY SCRIPT PYTHON
set -eu
rlt=$1
script=$2
python=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$rlt" eval --env HideAndSeek --policy Hider=scripted --policy Seeker=still --param level=1 \
  --episodes 2 --seed 1 --record "$dir/episodes.json" > /dev/null
out=$("$python" "$script" "$dir/episodes.json")
echo "$out"
echo "$out" | grep -q "grab 1.0, lock 1.0, unlock 0.0"
echo "$out" | grep -q "locks within 0.8 m of an open opening: 2 of 2"
echo "$out" | grep -q "props with a fort (2)"
echo "$out" | grep -Eq "the panel between the drone and its opening in (0\.9[0-9]|1\.00) of the frames"
echo "$out" | grep -Eq "holds: 1.0 per episode; let go in the frame they began \(grabbed and locked at once\) 0.00, held 0.5 s or more 1.00, which took their prop 1\.[0-9]{2} m towards its opening"
echo "$out" | grep -q "locked within 0.8 m of its opening when the prep phase ended: prop 0 in 1.00 of the episodes"
echo "$out" | grep -q "1 closed: 2 episodes, tagged in 0.00"
"$python" - "$dir/made_up.json" <<'MADE_UP'
import json, sys
events = {0: [("grab", 0)], 6: [("lock", 0)], 12: [("unlock", 0), ("grab", 0)], 18: [("lock", 0)],
          60: [("unlock", 1)], 66: [("lock", 0)], 120: [("unlock", 0)], 126: [("lock", 0)]}
frames = []
for index in range(131):
    frame = {"poses": [[0, 1, -1, 0, 0, 0, 1], [1, 1, -1, 0, 0, 0, 1], [0, 1, 0, 0, 0, 0, 1]]}
    listed = [{"type": kind, "body": body, "other": 2} for kind, body in events.get(index, [])]
    if index == 130:
        listed.append({"type": "prep_end", "body": -1, "other": -1})
    if listed:
        frame["events"] = listed
    frames.append(frame)
hider = {"kind": "hider", "shape": "sphere", "size": [0.3], "dynamic": True, "pose": [0, 1, 0, 0, 0, 0, 1]}
episode = {
    "env": "HideAndSeek", "frame_rate": 50,
    "metrics": {"fort_rate": 0, "openings_closed": 0, "tag_rate": 0, "hidden_fraction": 1},
    "bodies": [dict(hider, agent_id=0), dict(hider, agent_id=1),
               {"kind": "prop", "shape": "box", "size": [1.5, 1.9, 0.2], "agent_id": -1, "dynamic": True,
                "pose": [0, 1, 0, 0, 0, 0, 1]}],
    "openings": [{"kind": "doorway", "centre": [0, 0.95, 4], "normal": [0, 0, 1], "width": 1.4, "height": 1.9,
                  "open": True}],
    "dynamic_bodies": [0, 1, 2], "frames": frames}
json.dump({"format": "rlt-recording", "version": 1, "episodes": [episode]}, open(sys.argv[1], "w"))
MADE_UP
out=$("$python" "$script" "$dir/made_up.json")
echo "$out"
echo "$out" | grep -q "locks within 0.8 m of an open opening: 0 of 4"
echo "$out" | grep -q "of the 4 locks away from the openings: re-gripped (unlocked by the same drone within 0.5 s) 0.25, unlocked by another drone 0.25, unlocked later 0.25, still locked 0.25"
echo '{}' > "$dir/not_a_recording.json"
if "$python" "$script" "$dir/not_a_recording.json" 2> "$dir/error"; then
  echo "a file that is not a recording was read" >&2
  exit 1
fi
grep -q "is not an rlt recording" "$dir/error"
