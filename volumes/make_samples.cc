// Writes the small generated sample inputs of volumes/ (volumes/README.md) into a folder, the same
// bytes on every machine: the README's examples run on them. Plain text files are written by hand
// and the fog volume with OpenVDB itself, as another OpenVDB tool would write it; nothing here
// uses d2vdb. Build and run from the repository root:
//   g++ -std=c++17 -O1 volumes/make_samples.cc -o /tmp/make_samples -lopenvdb -ltbb
//   /tmp/make_samples volumes
#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;
using Point = std::array<double, 3>;

// Uniform and normal numbers from std::mt19937's raw output, whose sequence the C++ standard fixes
// (the standard's distributions are not portable bit for bit).
class PortableRandom {
 public:
  explicit PortableRandom(std::uint32_t start) : engine_(start) {}
  /// Uniform in (0, 1).
  double uniform() { return (static_cast<double>(engine_()) + 0.5) / 4294967296.0; }
  /// Standard normal (Box and Muller, 1958).
  double normal() {
    const double radius = std::sqrt(-2.0 * std::log(uniform()));
    return radius * std::cos(2.0 * kPi * uniform());
  }

 private:
  std::mt19937 engine_;
};

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  const std::string written(text);
  return written == "-0.0000" ? "0.0000" : written;
}

std::ofstream openFile(const std::string& folder, const std::string& name) {
  std::ofstream out(folder + "/" + name, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + folder + "/" + name);
  return out;
}

// A closed 2D polyline of 64 points on the ellipse with semi-axes 2 and 1.
void writeEllipse(const std::string& folder) {
  std::ofstream out = openFile(folder, "ellipse.json");
  out << "{\"type\": \"polyline\", \"version\": 1, \"dimension\": 2, \"closed\": true,\n"
         " \"points\": [";
  for (int i = 0; i < 64; ++i) {
    const double t = 2.0 * kPi * i / 64;
    out << (i == 0 ? "" : ", ") << (i % 6 == 5 ? "\n  " : "") << "[" << number(2 * std::cos(t))
        << ", " << number(std::sin(t)) << "]";
  }
  out << "]}\n";
}

// 200 noisy samples (normal noise of 0.01 per coordinate) of the closed space curve
// (cos t, sin t, 0.3 cos 2t), in random order.
void writeCloud(const std::string& folder) {
  PortableRandom random(2002);
  std::ofstream out = openFile(folder, "cloud.xyz");
  out << "# 200 samples of (cos t, sin t, 0.3 cos 2t) with normal noise of 0.01 per coordinate\n";
  for (int i = 0; i < 200; ++i) {
    const double t = 2.0 * kPi * random.uniform();
    const Point p{std::cos(t), std::sin(t), 0.3 * std::cos(2 * t)};
    for (int axis = 0; axis < 3; ++axis) {
      out << (axis == 0 ? "" : " ") << number(p[axis] + 0.01 * random.normal());
    }
    out << "\n";
  }
}

// A clamped cubic B-spline with 25 control points along the helix of radius 1 and pitch 0.4
// (three turns about +z): control points 45 degrees apart at radius 3 / (2 + cos 45 degrees),
// where a uniform cubic B-spline's points lie on the circle of radius 1 at the knots.
void writeHelix(const std::string& folder) {
  constexpr int kCount = 25, kDegree = 3;
  const double step = kPi / 4, radius = 3.0 / (2.0 + std::cos(step));
  std::ofstream out = openFile(folder, "helix.json");
  out << "{\"type\": \"bspline_curve\", \"version\": 1, \"dimension\": 3, \"degree\": " << kDegree
      << ", \"closed\": false,\n \"knots\": [";
  const int interior = kCount - kDegree - 1;
  for (int i = 0; i < kCount + kDegree + 1; ++i) {
    const int k = std::clamp(i - kDegree, 0, interior + 1);
    out << (i == 0 ? "" : ", ") << number(static_cast<double>(k) / (interior + 1));
  }
  out << "],\n \"control_points\": [";
  for (int i = 0; i < kCount; ++i) {
    const double angle = step * i;
    out << (i == 0 ? "" : ",") << (i % 3 == 0 ? "\n  " : " ") << "["
        << number(radius * std::cos(angle)) << ", " << number(radius * std::sin(angle)) << ", "
        << number(0.4 * angle / (2 * kPi)) << "]";
  }
  out << "]}\n";
}

// A scan of a wavy sheet: a 16 x 16 grid over [-1, 1]^2 jittered by up to a quarter cell, on
// z = 0.2 sin(pi x / 2) cos(pi y / 2), with normal noise of 0.003 in z.
void writeScan(const std::string& folder) {
  PortableRandom random(1202);
  std::ofstream out = openFile(folder, "scan.xyz");
  out << "# 256 samples of z = 0.2 sin(pi x/2) cos(pi y/2) over [-1, 1]^2, noise 0.003 in z\n";
  const double cell = 2.0 / 16;
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) {
      const double x = -1 + cell * (i + 0.5 + 0.5 * (random.uniform() - 0.5));
      const double y = -1 + cell * (j + 0.5 + 0.5 * (random.uniform() - 0.5));
      const double z = 0.2 * std::sin(kPi * x / 2) * std::cos(kPi * y / 2);
      out << number(x) << " " << number(y) << " " << number(z + 0.003 * random.normal()) << "\n";
    }
  }
}

// An ASCII PLY mesh with vertex normals; `triangles` index `points`.
void writePly(const std::string& folder, const std::string& name, const std::string& comment,
              const std::vector<Point>& points, const std::vector<Point>& normals,
              const std::vector<std::array<int, 3>>& triangles) {
  std::ofstream out = openFile(folder, name);
  out << "ply\nformat ascii 1.0\ncomment " << comment << "\nelement vertex " << points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
         "property float ny\nproperty float nz\nelement face "
      << triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) out << number(points[i][axis]) << " ";
    for (int axis = 0; axis < 3; ++axis) out << number(normals[i][axis]) << (axis < 2 ? " " : "\n");
  }
  for (const std::array<int, 3>& t : triangles) {
    out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  }
}

Point normalized(const Point& p) {
  const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return {p[0] / length, p[1] / length, p[2] / length};
}

// The open band x^2 + y^2 - z^2 = 1, |z| <= 0.5, of a hyperboloid of one sheet: 24 x 5 vertices,
// normals (x, y, -z) normalised, triangles wound counter-clockwise seen from the normals' side.
void writeHyperboloid(const std::string& folder) {
  constexpr int kAround = 24, kRings = 5;
  std::vector<Point> points, normals;
  for (int ring = 0; ring < kRings; ++ring) {
    const double z = -0.5 + 1.0 * ring / (kRings - 1), rho = std::sqrt(1 + z * z);
    for (int i = 0; i < kAround; ++i) {
      const double angle = 2 * kPi * i / kAround;
      const Point p{rho * std::cos(angle), rho * std::sin(angle), z};
      points.push_back(p);
      normals.push_back(normalized({p[0], p[1], -p[2]}));
    }
  }
  std::vector<std::array<int, 3>> triangles;
  for (int ring = 0; ring + 1 < kRings; ++ring) {
    for (int i = 0; i < kAround; ++i) {
      const int a = ring * kAround + i, b = ring * kAround + (i + 1) % kAround;
      const int c = b + kAround, d = a + kAround;
      triangles.push_back({a, b, c});
      triangles.push_back({a, c, d});
    }
  }
  writePly(folder, "hyperboloid.ply",
           "band |z| <= 0.5 of the hyperboloid x^2 + y^2 - z^2 = 1, exact normals", points, normals,
           triangles);
}

// The ellipsoid with semi-axes 2, 1.5 and 1: an icosahedron subdivided twice (162 vertices, 320
// triangles) on the unit sphere, scaled by the semi-axes, with the ellipsoid's exact normals.
void writeEllipsoid(const std::string& folder) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Point> sphere = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Point& p : sphere) p = normalized(p);
  std::vector<std::array<int, 3>> triangles = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < 2; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> edge = std::minmax(a, b);
      const auto found = midpoints.find(edge);
      if (found != midpoints.end()) return found->second;
      const Point& p = sphere[a];
      const Point& q = sphere[b];
      sphere.push_back(normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      return midpoints[edge] = static_cast<int>(sphere.size() - 1);
    };
    std::vector<std::array<int, 3>> finer;
    for (const std::array<int, 3>& t : triangles) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      finer.push_back({t[0], ab, ca});
      finer.push_back({t[1], bc, ab});
      finer.push_back({t[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles = finer;
  }
  const Point axes{2, 1.5, 1};
  std::vector<Point> points, normals;
  for (const Point& s : sphere) {
    points.push_back({axes[0] * s[0], axes[1] * s[1], axes[2] * s[2]});
    normals.push_back(normalized({s[0] / axes[0], s[1] / axes[1], s[2] / axes[2]}));
  }
  writePly(folder, "ellipsoid.ply", "ellipsoid with semi-axes 2, 1.5, 1, exact normals", points,
           normals, triangles);
}

// Distance to the union of three balls (negative inside), a puff of smoke.
double puffDistance(const openvdb::Vec3d& p) {
  const std::array<std::pair<openvdb::Vec3d, double>, 3> balls = {
      {{{0, 0, 0}, 0.5}, {{0.45, 0.1, 0.2}, 0.35}, {{-0.35, 0.3, -0.1}, 0.3}}};
  double distance = 1e300;
  for (const auto& [center, radius] : balls) {
    distance = std::min(distance, (p - center).length() - radius);
  }
  return distance;
}

// A fog volume as a simulation writes one: grid "density" of class fog volume, voxel 0.05,
// background 0, density 1 inside the puff falling linearly to 0 over 0.1 across its surface
// (0.5 on it), stored as half floats.
void writeSmoke(const std::string& folder) {
  constexpr double kVoxel = 0.05, kRamp = 0.1;
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(kVoxel));
  grid->setName("density");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  grid->setSaveFloatAsHalf(true);
  openvdb::FloatGrid::Accessor accessor = grid->getAccessor();
  for (int i = -20; i <= 20; ++i) {
    for (int j = -20; j <= 20; ++j) {
      for (int k = -20; k <= 20; ++k) {
        const double density = 0.5 - puffDistance(openvdb::Vec3d(i, j, k) * kVoxel) / kRamp;
        if (density > 0) {
          accessor.setValue({i, j, k}, static_cast<float>(std::min(density, 1.0)));
        }
      }
    }
  }
  grid->insertMeta("creator", openvdb::StringMetadata("volumes/make_samples.cc"));
  const openvdb::GridPtrVec grids{grid};
  openvdb::io::File file(folder + "/smoke.vdb");
  // zlib, which every OpenVDB build reads (Blosc is optional in OpenVDB builds).
  file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
  file.write(grids);
  file.close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_samples FOLDER\n";
    return 1;
  }
  try {
    openvdb::initialize();
    const std::string folder = argv[1];
    writeEllipse(folder);
    writeCloud(folder);
    writeHelix(folder);
    writeScan(folder);
    writeHyperboloid(folder);
    writeEllipsoid(folder);
    writeSmoke(folder);
  } catch (const std::exception& error) {
    std::cerr << "make_samples: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
