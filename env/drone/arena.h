// Arena: the static world of the hide-and-seek env (SPEC.md section 6, "Arena" and "Curriculum
// levels") built into a BulletWorld: floor, ceiling, four boundary walls and a room (the safe
// house) in the middle made of four L-shaped wall pieces reaching the ceiling, with four openings.
//
// Layout (metres, y up, the arena centred on x = z = 0): the floor's top face is y = 0, the
// ceiling's bottom face is y = height. The room's walls are centred on x = +-room_half and
// z = +-room_half. Each side of the room has one opening centred on it:
//   opening 0: doorway in the -z wall, opening 1: doorway in the +z wall,
//   opening 2: window in the +x wall,  opening 3: window in the -x wall.
// A side wall is a full-height segment from each corner to its opening (the two segments meeting at
// a corner form one L-shaped piece), plus a lintel above a doorway or a sill and a lintel around a
// window. An opening the level does not use is closed by a wall chunk that fills it exactly.
// Levels: 1 opens opening 0; 2 opens 0 and 1; 3 opens 0, 1, 2; 4 opens all four.
// With `doorways_swapped` the two doorways trade walls (opening 0 in the +z wall, opening 1 in the
// -z wall): since the room is the same seen from either side, at levels 1 and 2 that is the arena
// turned half round about the vertical, so level 1's one doorway can be met in either wall.
// Every static box is tagged kWall.
// With `room` = false the arena is only floor, ceiling and boundary walls: no room boxes, no
// openings (openings() is empty, inside_room() is always false); the drone tasks use this.
#ifndef RLT_ENV_DRONE_ARENA_H_
#define RLT_ENV_DRONE_ARENA_H_

#include <btBulletDynamicsCommon.h>

#include <vector>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

struct ArenaParams {
  int level = 4;                // curriculum level, 1-4
  float half_size = 12.0f;      // half the floor side (m): a 24 x 24 m floor
  float height = 6.0f;          // ceiling height (m)
  float wall_thickness = 0.2f;  // every wall, floor and ceiling slab (m)
  float room_half = 4.0f;       // half the room side, to the wall centre lines (m): about 8 x 8 m
  float door_width = 1.4f;      // doorway width (m)
  float door_height = 1.9f;     // doorway height from the floor (m)
  float window_width = 1.4f;    // window width (m)
  float window_height = 1.4f;   // window height (m)
  float window_sill = 2.2f;     // height of a window's bottom edge above the floor (m)
  bool room = true;             // build the room; false: an open arena (level is then ignored)
  bool doorways_swapped = false;  // opening 0 in the +z wall and opening 1 in the -z wall
};

inline constexpr int kMinLevel = 1;
inline constexpr int kMaxLevel = 4;
inline constexpr int kNumOpenings = 4;

struct Opening {
  enum Kind { kDoorway = 0, kWindow = 1 };
  Kind kind;
  btVector3 centre;  // centre of the hole, on the wall's centre plane
  float width;       // horizontal size (m)
  float height;      // vertical size (m)
  btVector3 normal;  // unit, horizontal, pointing out of the room
  bool open;         // open at this level (otherwise a wall chunk fills it)
};

// the number of openings open at `level` (1, 2, 3, 4)
int open_openings_at_level(int level);

// the fraction of the opening's area that `body` (e.g. a locked prop) covers: the opening is
// sampled on a samples x samples grid of cell centres, and a sample counts as covered when a ray
// along the normal from `depth` outside the wall plane to `depth` inside hits the body. An opening
// counts as closed (SPEC section 6) when a locked prop covers most of it, e.g. a fraction > 0.5.
float covered_fraction(const Opening& opening, const btCollisionObject& body, float depth = 0.5f,
                       int samples = 8);

// covered_fraction and, from the same rays, a graded share for shaping: the rays go on to
// fade_depth inside (when deeper than depth), and a sample whose hit lies deeper inside than
// depth counts less, linearly down to 0 at fade_depth (with fade_depth <= depth, graded =
// covered).
struct CoverShares {
  float covered = 0.0f;  // covered_fraction(opening, body, depth, samples)
  float graded = 0.0f;   // in [0, covered + the share hit between depth and fade_depth]
};
CoverShares cover_shares(const Opening& opening, const btCollisionObject& body, float fade_depth,
                         float depth = 0.5f, int samples = 8);

class Arena {
 public:
  // adds the static boxes to `world`; they live until the world is reset or destroyed.
  // level must be in [1, 4] when `room` is set (throws std::invalid_argument otherwise)
  Arena(BulletWorld& world, const ArenaParams& params = {});

  const std::vector<Opening>& openings() const { return openings_; }
  int num_open() const;
  // strictly inside the room's inner faces and between floor and ceiling
  bool inside_room(const btVector3& point) const;
  // inside the boundary walls' inner faces and between floor and ceiling
  bool inside_arena(const btVector3& point) const;
  const ArenaParams& params() const { return params_; }
  int num_boxes() const { return num_boxes_; }

 private:
  // a box on room side `side` (0: -z, 1: +z, 2: +x, 3: -x, whatever the openings' order)
  // spanning tangential [a, b] and heights [y0, y1]
  void add_side_box(int side, float a, float b, float y0, float y1);

  BulletWorld& world_;
  ArenaParams params_;
  std::vector<Opening> openings_;
  int num_boxes_ = 0;
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_ARENA_H_
