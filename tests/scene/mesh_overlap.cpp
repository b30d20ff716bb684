// Overlap checks (mesh_overlap.h): planes hashed into buckets for the coplanar pairs, a uniform
// grid over each closed piece for the crossings.
#include "mesh_overlap.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gtbake::test {
namespace {

using Vec = Eigen::Vector3d;
using Box = Eigen::AlignedBox3d;

// Coplanar faces also agree in direction to within this angle, rad (float rounding tilts a 1 cm
// triangle 10 m from the origin by 1e-4).
constexpr double kParallelAngle = 1e-3;

struct Tri {
  std::array<Vec, 3> v;
  Vec n = Vec::Zero();  // unit geometric normal (b − a) × (c − a); zero if degenerate
  double area = 0.0;
  Box box;
};

std::vector<Tri> trianglesOf(const Scene& scene) {
  std::vector<Tri> out(scene.triangles.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    Tri& t = out[i];
    for (int k = 0; k < 3; ++k) {
      t.v[k] = scene.positions[scene.triangles[i][k]].cast<double>();
      t.box.extend(t.v[k]);
    }
    const Vec cross = (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]);
    t.area = 0.5 * cross.norm();
    if (t.area > 0.0) t.n = cross.normalized();
  }
  return out;
}

Box grown(const Box& box) {
  return Box(box.min().array() - kTouchTolerance, box.max().array() + kTouchTolerance);
}

struct Pieces {
  std::vector<int> of;  // piece of each triangle
  std::vector<bool> closed;
  std::vector<Box> box;
  std::vector<std::vector<int>> members;
};

int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

Pieces findPieces(const Scene& scene, const std::vector<Tri>& tris) {
  std::unordered_map<std::uint64_t, std::vector<int>> uses;  // undirected edge → triangles
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = scene.triangles[i][k], b = scene.triangles[i][(k + 1) % 3];
      uses[(std::min(a, b) << 32) | std::max(a, b)].push_back(static_cast<int>(i));
    }
  }
  std::vector<int> parent(tris.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [edge, ts] : uses) {
    if (ts.size() == 2) parent[root(parent, ts[0])] = root(parent, ts[1]);
  }
  Pieces p;
  p.of.resize(tris.size());
  std::unordered_map<int, int> index;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const auto [it, added] = index.emplace(root(parent, static_cast<int>(i)), p.members.size());
    if (added) p.members.emplace_back();
    p.of[i] = it->second;
    p.members[it->second].push_back(static_cast<int>(i));
  }
  p.closed.assign(p.members.size(), true);
  p.box.resize(p.members.size());
  for (std::size_t i = 0; i < tris.size(); ++i) p.box[p.of[i]].extend(tris[i].box);
  for (const auto& [edge, ts] : uses) {
    for (int t : ts) {
      const auto same =
          std::count_if(ts.begin(), ts.end(), [&](int u) { return p.of[u] == p.of[t]; });
      if (same != 2) p.closed[p.of[t]] = false;
    }
  }
  return p;
}

std::string where(const char* what, const Tri& a, const Tri& b) {
  const Vec c = (a.v[0] + a.v[1] + a.v[2] + b.v[0] + b.v[1] + b.v[2]) / 6.0;
  std::ostringstream s;
  s << what << " near (" << c.x() << ", " << c.y() << ", " << c.z() << "), normals (" << a.n.x()
    << ", " << a.n.y() << ", " << a.n.z() << ") and (" << b.n.x() << ", " << b.n.y() << ", "
    << b.n.z() << ")";
  return s.str();
}

// ---- coplanar pairs ----

bool coplanar(const Tri& a, const Tri& b) {
  if (std::abs(a.n.dot(b.n)) < std::cos(kParallelAngle)) return false;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(a.n.dot(b.v[k] - a.v[0])) > kTouchTolerance) return false;
    if (std::abs(b.n.dot(a.v[k] - b.v[0])) > kTouchTolerance) return false;
  }
  return true;
}

// Area of b's projection onto a's plane clipped by a (Sutherland–Hodgman).
double overlapArea(const Tri& a, const Tri& b) {
  const Vec u = a.n.unitOrthogonal(), w = a.n.cross(u);  // a is counter-clockwise in (u, w)
  const auto flat = [&](const Vec& p) {
    return Eigen::Vector2d((p - a.v[0]).dot(u), (p - a.v[0]).dot(w));
  };
  // A triangle clipped by three half-planes keeps at most six vertices.
  std::array<Eigen::Vector2d, 6> poly = {flat(b.v[0]), flat(b.v[1]), flat(b.v[2])}, kept;
  std::size_t size = 3;
  for (int k = 0; k < 3 && size > 0; ++k) {
    const Eigen::Vector2d c0 = flat(a.v[k]), c1 = flat(a.v[(k + 1) % 3]);
    const auto side = [&](const Eigen::Vector2d& p) {
      const Eigen::Vector2d e = c1 - c0, q = p - c0;
      return e.x() * q.y() - e.y() * q.x();
    };
    std::size_t count = 0;
    for (std::size_t i = 0; i < size; ++i) {
      const Eigen::Vector2d& p = poly[i];
      const Eigen::Vector2d& q = poly[(i + 1) % size];
      const double sp = side(p), sq = side(q);
      if (sp >= 0.0 && count < kept.size()) kept[count++] = p;
      if ((sp >= 0.0) != (sq >= 0.0) && count < kept.size()) {
        kept[count++] = p + (sp / (sp - sq)) * (q - p);
      }
    }
    poly = kept;
    size = count;
  }
  double twice = 0.0;
  for (std::size_t i = 0; i < size; ++i) {
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d& q = poly[(i + 1) % size];
    twice += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(twice);
}

using Key = std::array<std::int64_t, 4>;

// (bucket, triangle) for every bucket of (normal, offset) a triangle's tolerances reach, sorted
// by bucket (cells centred on round values, so axis-aligned faces fall in one); the normal's sign
// is chosen so that its largest component is positive (coplanar faces facing either way meet).
std::vector<std::pair<Key, int>> planeBuckets(const std::vector<Tri>& tris) {
  constexpr double kNormalCell = 0.01, kOffsetCell = 0.05;
  constexpr double kReach[4] = {kParallelAngle / kNormalCell, kParallelAngle / kNormalCell,
                                kParallelAngle / kNormalCell, 0.1};  // offset: 5 mm
  std::vector<std::pair<Key, int>> entries;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const Tri& t = tris[i];
    if (t.area == 0.0) continue;
    Eigen::Index largest = 0;
    t.n.cwiseAbs().maxCoeff(&largest);
    const Vec m = t.n[largest] < 0.0 ? Vec(-t.n) : t.n;
    const double value[4] = {m.x() / kNormalCell, m.y() / kNormalCell, m.z() / kNormalCell,
                             m.dot(t.v[0]) / kOffsetCell};
    Key lo{}, hi{};
    for (int c = 0; c < 4; ++c) {
      lo[c] = std::llround(value[c] - kReach[c]);
      hi[c] = std::llround(value[c] + kReach[c]);
    }
    for (Key k = lo; k[0] <= hi[0]; ++k[0]) {
      for (k[1] = lo[1]; k[1] <= hi[1]; ++k[1]) {
        for (k[2] = lo[2]; k[2] <= hi[2]; ++k[2]) {
          for (k[3] = lo[3]; k[3] <= hi[3]; ++k[3]) entries.emplace_back(k, static_cast<int>(i));
        }
      }
    }
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

// Pairs of triangles sharing a bucket whose boxes overlap (sweep and prune along x).
std::vector<std::pair<int, int>> candidatePairs(const std::vector<Tri>& tris) {
  const auto entries = planeBuckets(tris);
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> ids;
  for (std::size_t begin = 0, end = 0; begin < entries.size(); begin = end) {
    ids.clear();
    for (end = begin; end < entries.size() && entries[end].first == entries[begin].first; ++end) {
      ids.push_back(entries[end].second);
    }
    std::sort(ids.begin(), ids.end(),
              [&](int a, int b) { return tris[a].box.min().x() < tris[b].box.min().x(); });
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Box box = grown(tris[ids[i]].box);
      for (std::size_t j = i + 1; j < ids.size(); ++j) {
        if (tris[ids[j]].box.min().x() > box.max().x()) break;
        if (box.intersects(tris[ids[j]].box)) {
          pairs.emplace_back(std::min(ids[i], ids[j]), std::max(ids[i], ids[j]));
        }
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

void findCoplanarOverlaps(const std::vector<Tri>& tris, OverlapReport& report) {
  for (const auto& [i, j] : candidatePairs(tris)) {
    const Tri &a = tris[i], &b = tris[j];
    if (!coplanar(a, b)) continue;
    const double area = overlapArea(a, b);
    // Clipping two triangles that share an edge leaves ~1e-16 of their area; a real overlap is
    // a sizeable part of the smaller one (the faces found here overlap by 10 % or more).
    if (area <= kOverlapFraction * std::min(a.area, b.area)) continue;
    if (a.n.dot(b.n) > 0.0) {
      if (report.coincident++ == 0) {
        report.first = where("coincident faces", a, b);
      }
    } else {
      ++report.contacts;
    }
  }
}

// ---- crossing surfaces ----

// The segment p–q passes through t's interior: ends on opposite sides of its plane and the
// crossing point inside every edge, each by more than kTouchTolerance.
bool segmentCrosses(const Vec& p, const Vec& q, const Tri& t) {
  const double dp = t.n.dot(p - t.v[0]), dq = t.n.dot(q - t.v[0]);
  const bool apart = (dp > kTouchTolerance && dq < -kTouchTolerance) ||
                     (dp < -kTouchTolerance && dq > kTouchTolerance);
  if (!apart) return false;
  const Vec x = p + (dp / (dp - dq)) * (q - p);
  for (int k = 0; k < 3; ++k) {
    const Vec inward = t.n.cross(t.v[(k + 1) % 3] - t.v[k]).normalized();
    if (inward.dot(x - t.v[k]) <= kTouchTolerance) return false;
  }
  return true;
}

bool trianglesCross(const Tri& a, const Tri& b) {
  if (a.area == 0.0 || b.area == 0.0) return false;
  for (int k = 0; k < 3; ++k) {
    if (segmentCrosses(a.v[k], a.v[(k + 1) % 3], b)) return true;
    if (segmentCrosses(b.v[k], b.v[(k + 1) % 3], a)) return true;
  }
  return false;
}

// Uniform grid of triangle ids over a box, about one triangle per cell.
class Grid {
 public:
  Grid(const Box& box, std::size_t items)
      : box_(box),
        cells_(std::clamp(static_cast<int>(std::cbrt(static_cast<double>(items))), 1, 32)),
        ids_(static_cast<std::size_t>(cells_ * cells_ * cells_)) {}
  void insert(int id, const Box& box) {
    forCells(box, [&](std::vector<int>& cell) { cell.push_back(id); });
  }
  template <typename F>
  void forCells(const Box& box, F f) {
    std::array<int, 3> lo{}, hi{};
    for (int c = 0; c < 3; ++c) {
      const double size = std::max(box_.sizes()[c], 1e-12) / cells_;
      lo[c] = std::clamp(static_cast<int>((box.min()[c] - box_.min()[c]) / size), 0, cells_ - 1);
      hi[c] = std::clamp(static_cast<int>((box.max()[c] - box_.min()[c]) / size), 0, cells_ - 1);
    }
    for (int x = lo[0]; x <= hi[0]; ++x) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int z = lo[2]; z <= hi[2]; ++z) f(ids_[(x * cells_ + y) * cells_ + z]);
      }
    }
  }

 private:
  Box box_;
  int cells_;
  std::vector<std::vector<int>> ids_;
};

// Crossings of closed piece c with the triangles of every open piece and of every later closed
// piece (each pair of pieces once).
void findCrossingsWith(int c, const std::vector<Tri>& tris, const Pieces& pieces,
                       std::vector<int>& seen, OverlapReport& report) {
  const Box box = grown(pieces.box[c]);
  Grid grid(box, pieces.members[c].size());
  for (int t : pieces.members[c]) grid.insert(t, grown(tris[t].box));
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const int other = pieces.of[t];
    if (other == c || (pieces.closed[other] && other < c) || !box.intersects(tris[t].box)) {
      continue;
    }
    grid.forCells(tris[t].box.intersection(box), [&](const std::vector<int>& cell) {
      for (int u : cell) {
        if (seen[u] == static_cast<int>(t)) continue;
        seen[u] = static_cast<int>(t);
        if (trianglesCross(tris[t], tris[u]) && report.crossings++ == 0 && report.first.empty()) {
          report.first = where("crossing surfaces", tris[t], tris[u]);
        }
      }
    });
  }
}

// Ray parity of p against closed piece c (direction skewed off every axis); nothing if the ray
// passes within kTouchTolerance of p's start on c's surface.
bool strictlyInside(const Vec& p, const std::vector<Tri>& tris, const std::vector<int>& members) {
  const Vec d = Vec(0.0123, 1.0, 0.0371).normalized();
  int hits = 0;
  for (int i : members) {
    const Tri& t = tris[i];
    const Vec e1 = t.v[1] - t.v[0], e2 = t.v[2] - t.v[0], s = p - t.v[0];
    const Vec h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-15) continue;
    const double u = s.dot(h) / det;
    const Vec q = s.cross(e1);
    const double v = d.dot(q) / det, dist = e2.dot(q) / det;
    if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
    if (std::abs(dist) <= kTouchTolerance) return false;
    hits += dist > 0.0;
  }
  return hits % 2 == 1;
}

void findEnclosed(const std::vector<Tri>& tris, const Pieces& pieces, OverlapReport& report) {
  for (std::size_t x = 0; x < pieces.members.size(); ++x) {
    for (std::size_t c = 0; c < pieces.members.size(); ++c) {
      if (c == x || !pieces.closed[c] || !grown(pieces.box[c]).contains(pieces.box[x])) continue;
      const Vec& p = tris[pieces.members[x].front()].v[0];
      if (strictlyInside(p, tris, pieces.members[c])) ++report.enclosed;
    }
  }
}

}  // namespace

OverlapReport findOverlaps(const Scene& scene) {
  const std::vector<Tri> tris = trianglesOf(scene);
  const Pieces pieces = findPieces(scene, tris);
  OverlapReport report;
  report.pieces = pieces.members.size();
  report.closed_pieces =
      static_cast<std::size_t>(std::count(pieces.closed.begin(), pieces.closed.end(), true));
  findCoplanarOverlaps(tris, report);
  std::vector<int> seen(tris.size(), -1);
  for (std::size_t c = 0; c < pieces.members.size(); ++c) {
    if (pieces.closed[c]) findCrossingsWith(static_cast<int>(c), tris, pieces, seen, report);
  }
  findEnclosed(tris, pieces, report);
  return report;
}

}  // namespace gtbake::test
