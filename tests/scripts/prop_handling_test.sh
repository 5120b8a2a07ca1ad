#!/bin/sh
# scripts/prop_handling.py on two episodes of the scripted hider at level 1 (one grab and one lock
# per episode, both locks at the doorway and the prop locked there at the end, both forts built,
# the panel pushed ahead of the drone, one hold per episode carried from about 2 m out to the
# doorway and let go by the lock, both episodes counted with one opening closed),
# and on a file that is not a recording.
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
echo '{}' > "$dir/not_a_recording.json"
if "$python" "$script" "$dir/not_a_recording.json" 2> "$dir/error"; then
  echo "a file that is not a recording was read" >&2
  exit 1
fi
grep -q "is not an rlt recording" "$dir/error"
