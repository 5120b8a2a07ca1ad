// Scripted policies of HideAndSeek (`rlt eval --policy Hider=scripted` / `Seeker=scripted`): they
// read the env's state directly and show that the mechanics allow the strategies we want to see
// emerge (SPEC.md section 6; issue 4).
//
// Seeker: flies at the nearest hider it sees. When it sees none it heads for the nearest hider in
// the game anyway (it knows where they are), through an open, unlocked-free opening of the room
// when one of them is inside and the other outside (a waypoint 1.5 m outside the opening, then one
// 1.5 m inside), around the room's corners when the room is in the way. It flies at doorway height.
// Hider: "drag a free prop into an open opening and lock it". The openings open at the level are
// taken in order of distance from the room's centre (doorways first); hider i keeps the i-th as its
// own until it is closed, then takes the first one still open that is no other hider's own. Of the
// unlocked props that no other hider holds or was given, it takes the one with the shortest way
// from the hider to it and on to the opening (horizontal). It flies to a point 1.1 m in front of
// the prop's broad face on the room's side (outside the room: on its own side), faces it and
// grabs; then carries it (the grab keeps the prop's pose in the drone's frame) to a staging point
// inside the room 1 m before the opening, turning so that the panel is square to the opening and
// between the drone and the wall, pushes it until it lies flat against the inner face of the wall
// over the opening, and locks it. A hider with no opening left stays where it is.
#pragma once

#include "env/drone/hide_and_seek.h"

namespace rlt::drone {

// writes actions for every slot of `team` that needs one; always true
bool write_scripted_hide_and_seek_actions(HideAndSeek& env, HideAndSeek::Team team,
                                          BehaviorView& view);

}  // namespace rlt::drone
