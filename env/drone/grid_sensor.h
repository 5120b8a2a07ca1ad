// GridSensor: the spherical grid sensor of the paper (SPEC.md section 6, "spatial grid" and
// "frontal grid"), after MBaske's Unity Grid Sensors (the spatial and frontal
// GridSensorComponent3D): cells in latitude and longitude around the agent, one channel per Tag,
// filled from SurfacePoints (points scanned on the colliders), not from per-cell raycasts.
//
// Frame (yaw only: the drone is upright): forward = the pose's +z turned into the horizontal plane,
// right = forward x up (as in DroneBody), up = +y. For a point at offset v from the pose's origin:
//   distance  d   = |v| (m),
//   longitude lon = atan2(v . right, v . forward): 0 = forward, positive to the drone's RIGHT,
//                   +-180 = behind (degrees),
//   latitude  lat = asin(v . up / d) (computed as atan2(v . up, horizontal distance)): +90 = up.
// Cells: the latitude range [-lat_south, +lat_north] is cut into lat_cells = round(range / arc)
// equal rows and the longitude range [-lon, +lon] into lon_cells = round(range / arc) equal columns
// (at least 1 each; the actual arcs are lat_arc_degrees() and lon_arc_degrees()).
// Output order, row-major [lat_cells, lon_cells, kNumTags] floats like an image of the view:
//   row 0 = northmost (up), rows go down; column 0 = leftmost (lon = -lon_degrees), columns go
//   right; channel = Tag (kWall, kProp, kObstacle, kHider, kSeeker).
// A point counts when d <= max_distance and its direction is inside both ranges (edges included).
// Nearest wins within each tag's channel, as in MBaske's GridSensorComponent3D (the sensor the
// paper used): each channel of a cell holds
//   (1 - (max(d, min_distance) - min_distance) / (max_distance - min_distance)) ^ normalization
// for the nearest point of that tag in the cell, and 0 when the cell has none. Tags do not occlude
// each other: a hider behind a wall shows in the hider channel of the cell that also shows the
// wall (the sensor senses what is around within max_distance; seeing is vision.h's business).
// Every value is in [0, 1] (points closer than min_distance give 1; normalization 1 = linear,
// < 1 stretches far ones).
// The observing body's own points (self_body, an index of SurfacePoints::body; -1 for none) are
// skipped.
// Cost: one vectorizable pass over the structure-of-arrays points (relative offset, yaw rotation,
// squared distance, fast_atan2 twice, sqrt), shared by every sensor of one observe_many() call,
// then per sensor a vectorizable (cell, tag) slot pass and a scalar nearest-wins scatter of
// distance keys into four interleaved banks (no store-to-load chains between neighbours). observe()
// and observe_many() are const and thread-safe (scratch space is per thread).
#ifndef RLT_ENV_DRONE_GRID_SENSOR_H_
#define RLT_ENV_DRONE_GRID_SENSOR_H_

#include <btBulletDynamicsCommon.h>

#include "env/drone/bullet_world.h"
#include "env/drone/surface_points.h"

namespace rlt::drone {

struct GridSensorParams {
  float lat_north_degrees = 90.0f;  // top of the latitude range (degrees above the horizon)
  float lat_south_degrees = 90.0f;  // bottom of the latitude range (degrees below the horizon)
  float lon_degrees = 180.0f;       // half range of longitude (180 = all around)
  float cell_arc_degrees = 30.0f;   // target cell size in both directions (degrees)
  float min_distance = 0.0f;        // proximity 1 at and below this distance (m)
  float max_distance = 20.0f;       // proximity 0 here; farther points are not seen (m)
  float normalization = 1.0f;       // exponent on the linear proximity (1 = linear, > 0)

  // all around (lat +-90, lon +-180), 30-degree cells, 20 m: [6, 12, kNumTags] = 360 floats
  static GridSensorParams spatial();
  // in front (lat +-90, lon +-84), 20-degree cells (21 x 20 exactly), 20 m: [9, 8, kNumTags] =
  // 360 floats. (15-degree cells would give [12, 11, kNumTags] = 660 floats.)
  static GridSensorParams frontal();
};

class GridSensor {
 public:
  // throws std::invalid_argument on empty ranges, a non-positive arc or normalization, or
  // max_distance <= min_distance
  explicit GridSensor(const GridSensorParams& params = GridSensorParams::spatial());

  int lat_cells() const { return lat_cells_; }
  int lon_cells() const { return lon_cells_; }
  int num_cells() const { return lat_cells_ * lon_cells_; }
  int size() const { return num_cells() * kNumTags; }  // floats written by observe()
  float lat_arc_degrees() const { return lat_arc_; }
  float lon_arc_degrees() const { return lon_arc_; }
  // the row-major cell (row * lon_cells + column) of a direction, or -1 outside the ranges
  int cell_of(float lat_degrees, float lon_degrees) const;
  const GridSensorParams& params() const { return params_; }

  // writes size() floats [lat_cells, lon_cells, kNumTags] seen from `pose` to `out`
  void observe(const SurfacePoints& points, int self_body, const btTransform& pose,
               float* out) const;
  // observes with `count` sensors in one pass over the points: sensors[k] writes outs[k]
  static void observe_many(const GridSensor* const* sensors, float* const* outs, int count,
                           const SurfacePoints& points, int self_body, const btTransform& pose);

 private:
  GridSensorParams params_;
  int lat_cells_, lon_cells_;
  float lat_arc_, lon_arc_;  // actual cell arcs (degrees)
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_GRID_SENSOR_H_
