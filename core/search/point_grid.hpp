#pragma once
// A uniform grid over a fixed set of points, for queries from other points ("which wall
// points lie within r of x?"). The neighbour search (core/search/neighbour_search.hpp) answers the
// same question within one particle set; this is its counterpart for static geometry such
// as the dummy wall layers of a boundary model.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/base/types.hpp"

namespace mps_lab {

class PointGrid {
 public:
  // `cell_size` (m) must be at least the radius of later queries.
  void build(std::vector<Vec2> points, double cell_size) {
    points_ = std::move(points);
    cell_ = cell_size;
    if (points_.empty()) return;
    low_ = points_.front();
    high_ = low_;
    for (const Vec2& p : points_) {
      low_ = low_.cwiseMin(p);
      high_ = high_.cwiseMax(p);
    }
    nx_ = static_cast<long long>((high_.x() - low_.x()) / cell_) + 1;
    ny_ = static_cast<long long>((high_.y() - low_.y()) / cell_) + 1;
    start_.assign(static_cast<std::size_t>(nx_ * ny_ + 1), 0);
    for (const Vec2& p : points_) ++start_[static_cast<std::size_t>(cell_of(p)) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    order_.resize(points_.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < points_.size(); ++k)
      order_[fill[static_cast<std::size_t>(cell_of(points_[k]))]++] = static_cast<std::uint32_t>(k);
  }

  const std::vector<Vec2>& points() const { return points_; }

  // Whether x lies within `radius` of the points' bounding box: the cheap test before a query
  // from a point that is far from all of them.
  bool may_reach(const Vec2& x, double radius) const {
    if (points_.empty()) return false;
    return (x.array() >= low_.array() - radius).all() && (x.array() <= high_.array() + radius).all();
  }

  // Calls f(k) for every point k with |points[k] - x| < radius, in a fixed order.
  template <class Visit>
  void for_each_within(const Vec2& x, double radius, Visit&& f) const {
    if (points_.empty()) return;
    const auto cx = static_cast<long long>(std::floor((x.x() - low_.x()) / cell_));
    const auto cy = static_cast<long long>(std::floor((x.y() - low_.y()) / cell_));
    const double r2 = radius * radius;
    for (long long j = std::max(cy - 1, 0LL); j <= std::min(cy + 1, ny_ - 1); ++j) {
      for (long long i = std::max(cx - 1, 0LL); i <= std::min(cx + 1, nx_ - 1); ++i) {
        const auto c = static_cast<std::size_t>(j * nx_ + i);
        for (std::uint32_t s = start_[c]; s < start_[c + 1]; ++s) {
          const std::uint32_t k = order_[s];
          if ((points_[k] - x).squaredNorm() < r2) f(k);
        }
      }
    }
  }

 private:
  long long cell_of(const Vec2& p) const {
    const auto i = std::min(static_cast<long long>((p.x() - low_.x()) / cell_), nx_ - 1);
    const auto j = std::min(static_cast<long long>((p.y() - low_.y()) / cell_), ny_ - 1);
    return j * nx_ + i;
  }
  std::vector<Vec2> points_;
  double cell_ = 1.0;
  Vec2 low_ = Vec2::Zero();
  Vec2 high_ = Vec2::Zero();
  long long nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> order_;
};

}  // namespace mps_lab
