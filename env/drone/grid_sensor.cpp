#include "env/drone/grid_sensor.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "env/drone/fast_atan2.h"

namespace rlt::drone {
namespace {

constexpr float kDegToRad = 3.14159265358979f / 180.0f;
// a distance key: the distance's float bits; for distances >= 0 the unsigned order is the distance
// order, so nearest wins = unsigned min
constexpr std::uint32_t kEmpty = 0xffffffffu;
// interleaved scatter banks: neighbouring points (often in the same slot) update different banks
constexpr int kBanks = 4;

// per-thread scratch of one observation, sized to the point cloud
struct Scratch {
  std::vector<float> lat;             // [n] latitude (rad)
  std::vector<float> lon;             // [n] longitude (rad), positive to the right
  std::vector<float> distance2;       // [n] squared distance (m^2)
  std::vector<std::uint32_t> key;     // [n] distance bits
  std::vector<std::int32_t> slot;     // [n] cell * kNumTags + tag of one sensor, size() = not seen
  std::vector<std::uint32_t> banks;   // [kBanks, num_cells * kNumTags + 1] nearest key per slot
};

thread_local Scratch scratch;

// the projection kernel over raw arrays of n points (kept out of line: GCC 12 vectorizes it here
// but not when inlined into project()); (ox, oy, oz) the origin, (fx, 0, fz) the unit forward and
// right = forward x up = (-fz, 0, fx)
__attribute__((noinline)) void project_kernel(int n, const float* __restrict px,
                                              const float* __restrict py,
                                              const float* __restrict pz, float ox, float oy,
                                              float oz, float fx, float fz, float* __restrict lat,
                                              float* __restrict lon, float* __restrict distance2,
                                              std::uint32_t* __restrict key) {
  for (int i = 0; i < n; ++i) {
    const float dx = px[i] - ox, dy = py[i] - oy, dz = pz[i] - oz;
    const float right = fz * -dx + fx * dz;
    const float forward = fx * dx + fz * dz;
    const float horizontal2 = right * right + forward * forward;
    const float d2 = horizontal2 + dy * dy;
    lon[i] = fast_atan2(right, forward);
    lat[i] = fast_atan2(dy, std::sqrt(horizontal2));
    distance2[i] = d2;
    const float d = std::sqrt(d2);
    std::memcpy(&key[i], &d, sizeof d);
  }
}

// distance, latitude and longitude of every point in the yaw frame of `pose`
void project(const SurfacePoints& points, const btTransform& pose, Scratch& s) {
  const int n = points.size();
  s.lat.resize(n);
  s.lon.resize(n);
  s.distance2.resize(n);
  s.key.resize(n);
  const btMatrix3x3& basis = pose.getBasis();
  float fx = basis[0][2], fz = basis[2][2];  // the body's +z, flattened
  const float norm = std::sqrt(fx * fx + fz * fz);
  if (norm > 1e-6f) {
    fx /= norm;
    fz /= norm;
  } else {
    fx = 0.0f;
    fz = 1.0f;
  }
  const btVector3& origin = pose.getOrigin();
  project_kernel(n, points.x(), points.y(), points.z(), origin.x(), origin.y(), origin.z(), fx, fz,
                 s.lat.data(), s.lon.data(), s.distance2.data(), s.key.data());
}

}  // namespace

GridSensorParams GridSensorParams::spatial() {
  GridSensorParams p;
  p.lat_north_degrees = 90.0f;
  p.lat_south_degrees = 90.0f;
  p.lon_degrees = 180.0f;
  p.cell_arc_degrees = 30.0f;
  p.max_distance = 20.0f;
  return p;
}

GridSensorParams GridSensorParams::frontal() {
  GridSensorParams p;
  p.lat_north_degrees = 90.0f;
  p.lat_south_degrees = 90.0f;
  p.lon_degrees = 84.0f;
  p.cell_arc_degrees = 20.0f;
  p.max_distance = 20.0f;
  return p;
}

GridSensor::GridSensor(const GridSensorParams& params) : params_(params) {
  const float lat_range = params_.lat_north_degrees + params_.lat_south_degrees;
  const float lon_range = 2.0f * params_.lon_degrees;
  if (!(lat_range > 0.0f) || !(lon_range > 0.0f) || params_.lat_north_degrees > 90.0f ||
      params_.lat_south_degrees > 90.0f || params_.lon_degrees > 180.0f) {
    throw std::invalid_argument("grid sensor: latitude and longitude ranges must be non-empty "
                                "and within +-90 and +-180 degrees");
  }
  if (!(params_.cell_arc_degrees > 0.0f) || !(params_.normalization > 0.0f) ||
      !(params_.max_distance > params_.min_distance) || params_.min_distance < 0.0f) {
    throw std::invalid_argument("grid sensor: need cell_arc > 0, normalization > 0 and "
                                "0 <= min_distance < max_distance");
  }
  lat_cells_ = std::max(1, static_cast<int>(std::lround(lat_range / params_.cell_arc_degrees)));
  lon_cells_ = std::max(1, static_cast<int>(std::lround(lon_range / params_.cell_arc_degrees)));
  lat_arc_ = lat_range / lat_cells_;
  lon_arc_ = lon_range / lon_cells_;
}

int GridSensor::cell_of(float lat_degrees, float lon_degrees) const {
  if (lat_degrees > params_.lat_north_degrees || lat_degrees < -params_.lat_south_degrees ||
      std::fabs(lon_degrees) > params_.lon_degrees) {
    return -1;
  }
  const int row = std::clamp(
      static_cast<int>((params_.lat_north_degrees - lat_degrees) / lat_arc_), 0, lat_cells_ - 1);
  const int column = std::clamp(
      static_cast<int>((lon_degrees + params_.lon_degrees) / lon_arc_), 0, lon_cells_ - 1);
  return row * lon_cells_ + column;
}

void GridSensor::observe(const SurfacePoints& points, int self_body, const btTransform& pose,
                         float* out) const {
  const GridSensor* self = this;
  observe_many(&self, &out, 1, points, self_body, pose);
}

void GridSensor::observe_many(const GridSensor* const* sensors, float* const* outs, int count,
                              const SurfacePoints& points, int self_body, const btTransform& pose) {
  Scratch& s = scratch;
  project(points, pose, s);
  const int n = points.size();
  s.slot.resize(n);

  for (int k = 0; k < count; ++k) {
    const GridSensor& sensor = *sensors[k];
    const GridSensorParams& p = sensor.params_;
    const int rows = sensor.lat_cells_, columns = sensor.lon_cells_;
    const int cells = rows * columns;
    const int slots = cells * kNumTags;
    const std::int32_t unseen = slots;  // the spare slot past the grid
    // the range checks; a full range is not checked (fast_atan2 may pass +-pi by ~1e-5)
    const float north = p.lat_north_degrees * kDegToRad;
    const float lat_high = p.lat_north_degrees >= 90.0f ? 1e30f : north;
    const float lat_low = p.lat_south_degrees >= 90.0f ? -1e30f : -p.lat_south_degrees * kDegToRad;
    const float lon_half = p.lon_degrees * kDegToRad;
    const float lon_limit = p.lon_degrees >= 180.0f ? 1e30f : lon_half;
    const float per_lat = 1.0f / (sensor.lat_arc_ * kDegToRad);
    const float per_lon = 1.0f / (sensor.lon_arc_ * kDegToRad);
    const float max_distance2 = p.max_distance * p.max_distance;

    // slot (cell and tag channel) of every point (vectorizable)
    const float* __restrict lat = s.lat.data();
    const float* __restrict lon = s.lon.data();
    const float* __restrict distance2 = s.distance2.data();
    const std::int32_t* __restrict tag = points.tag();  // in [0, kNumTags): SurfacePoints' rule
    std::int32_t* __restrict slot = s.slot.data();
    for (int i = 0; i < n; ++i) {
      const float row_f = std::max((north - lat[i]) * per_lat, 0.0f);
      const float column_f = std::max((lon[i] + lon_half) * per_lon, 0.0f);
      const std::int32_t row = std::min(static_cast<std::int32_t>(row_f), rows - 1);
      const std::int32_t column = std::min(static_cast<std::int32_t>(column_f), columns - 1);
      // & rather than &&: no branches in the loop
      const bool seen = (lat[i] <= lat_high) & (lat[i] >= lat_low) & (lon[i] <= lon_limit) &
                        (lon[i] >= -lon_limit) & (distance2[i] <= max_distance2);
      slot[i] = seen ? (row * columns + column) * kNumTags + tag[i] : unseen;
    }
    if (self_body >= 0) {
      const SurfaceBody& own = points.body(self_body);
      std::fill(slot + own.begin, slot + own.end, unseen);
    }

    // nearest wins within each tag's channel: unsigned min of distance keys, four banks
    // interleaved
    const int stride = slots + 1;
    s.banks.assign(static_cast<size_t>(kBanks) * stride, kEmpty);
    std::uint32_t* b0 = s.banks.data();
    std::uint32_t* b1 = b0 + stride;
    std::uint32_t* b2 = b1 + stride;
    std::uint32_t* b3 = b2 + stride;
    const std::uint32_t* key = s.key.data();
    int i = 0;
    for (; i + kBanks <= n; i += kBanks) {
      b0[slot[i]] = std::min(b0[slot[i]], key[i]);
      b1[slot[i + 1]] = std::min(b1[slot[i + 1]], key[i + 1]);
      b2[slot[i + 2]] = std::min(b2[slot[i + 2]], key[i + 2]);
      b3[slot[i + 3]] = std::min(b3[slot[i + 3]], key[i + 3]);
    }
    for (; i < n; ++i) b0[slot[i]] = std::min(b0[slot[i]], key[i]);

    // proximity of the nearest point of each channel of each cell (vectorizable: no branches)
    float* __restrict out = outs[k];
    const float min_distance = p.min_distance;
    const float per_span = 1.0f / (p.max_distance - p.min_distance);
    for (int c = 0; c < slots; ++c) {
      const std::uint32_t nearest = std::min(std::min(b0[c], b1[c]), std::min(b2[c], b3[c]));
      float d;
      std::memcpy(&d, &nearest, sizeof d);
      const float proximity = 1.0f - (std::max(d, min_distance) - min_distance) * per_span;
      out[c] = nearest == kEmpty ? 0.0f : std::clamp(proximity, 0.0f, 1.0f);
    }
    if (p.normalization != 1.0f)
      for (int c = 0; c < slots; ++c) out[c] = std::pow(out[c], p.normalization);
  }
}

}  // namespace rlt::drone
