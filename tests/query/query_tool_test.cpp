// algray-query end to end: run the binary on small CSV files and check the output
// against closed forms, and every kind of bad input against exit code 2.
#include "ray_csv.h"

#include "algray/gallery.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exitCode = -1;
  std::string err;
  std::vector<std::vector<double>> rows;  // OUT.csv without its header
  std::string header;
};

class QueryTool : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::path(ALGRAY_BINARY_DIR) / "query-test" /
          ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir);
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  // Runs algray-query with `args` (the output goes to dir/out.csv unless args name one).
  RunResult run(const std::string& args) {
    const fs::path out = dir / "out.csv", err = dir / "err.txt";
    fs::remove(out);
    const std::string cmd = std::string(ALGRAY_QUERY_EXE) + " " + args + " 2> " + err.string();
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream e(err);
    r.err.assign(std::istreambuf_iterator<char>(e), {});
    std::ifstream o(out);
    std::getline(o, r.header);
    std::string line;
    while (std::getline(o, line)) {
      std::vector<double> row;
      std::stringstream s(line);
      std::string field;
      while (std::getline(s, field, ',')) row.push_back(std::stod(field));
      r.rows.push_back(row);
    }
    return r;
  }
  std::string common(const fs::path& rays) {
    return "--rays " + rays.string() + " --out " + (dir / "out.csv").string();
  }
};

// First root of |o + t d|^2 = r^2 beyond tnear (closed form, long double).
double sphereT(const double o[3], const double d[3], double r, double tnear) {
  long double a = 0, b = 0, c = -(long double)r * r;
  for (int i = 0; i < 3; ++i) {
    a += (long double)d[i] * d[i];
    b += 2.0L * o[i] * d[i];
    c += (long double)o[i] * o[i];
  }
  const long double disc = b * b - 4 * a * c;
  if (disc < 0) return -1;
  const long double q = -0.5L * (b + (b < 0 ? -1 : 1) * std::sqrt(disc));
  long double t0 = q / a, t1 = c / q;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > tnear) return (double)t0;
  if (t1 > tnear) return (double)t1;
  return -1;
}

TEST_F(QueryTool, SphereMatchesClosedFormInAnyColumnOrder) {
  // Columns shuffled, an extra column, a direction that is not unit length.
  const double rays[][8] = {{0, 0, -5, 0, 0, 1, 0, 1e30},     {0.3, -0.2, -4, 0, 0, 2.5, 0, 100},
                            {3, 0, 0, -1, 0.1, 0.05, 0, 100}, {5, 5, 5, 1, 0, 0, 0, 100},
                            {0, 0, 0, 0.2, 0.3, 0.1, 0, 100}, {0, 0, -5, 0, 0, 1, 4.5, 100},
                            {0, 0, -5, 0, 0, 1, 0, 3.9}};
  std::string csv = "id,tfar,dz,dy,dx,oz,oy,ox,tnear\n";
  char buf[512];
  for (int i = 0; i < 7; ++i) {
    const double* r = rays[i];
    std::snprintf(buf, sizeof buf, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i, r[7],
                  r[5], r[4], r[3], r[2], r[1], r[0], r[6]);
    csv += buf;
  }
  const RunResult r =
      run("--surface \"x^2 + y^2 + z^2 - 1\" --clip-sphere 1.5 " + common(write("rays.csv", csv)));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.header, "hit,t,nx,ny,nz");
  EXPECT_NE(r.err.find("rays/s"), std::string::npos) << r.err;
  ASSERT_EQ(r.rows.size(), 7u);
  for (int i = 0; i < 7; ++i) {
    const double t = sphereT(rays[i], rays[i] + 3, 1.0, rays[i][6]);
    const bool expectHit = t > 0 && t < rays[i][7];
    ASSERT_EQ(r.rows[i].size(), 5u);
    EXPECT_EQ(r.rows[i][0], expectHit ? 1.0 : 0.0) << i;
    if (!expectHit) {
      for (int k = 1; k < 5; ++k) EXPECT_EQ(r.rows[i][k], 0.0);
      continue;
    }
    EXPECT_NEAR(r.rows[i][1], t, 1e-14 * t) << i;
    double p[3], len = 0;
    for (int k = 0; k < 3; ++k) p[k] = rays[i][k] + t * rays[i][3 + k];
    for (int k = 0; k < 3; ++k) len += r.rows[i][2 + k] * r.rows[i][2 + k];
    EXPECT_NEAR(len, 1.0, 1e-14);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.rows[i][2 + k], p[k], 1e-12) << i;
  }
}

// A clip region far larger than the surface (a unit sphere in clip balls and boxes of
// 1e3 to 1e14 radii): every ray hits as the closed form says, in both channels, without an
// org_error column (whose default, the rounding of a hit point of a ray from up to 32
// object sizes away, took the clip radius for the object's size: from 1e14 an uncertainty
// of 2.1 at every origin, and every ray missed; --float, whose origins carry 16 float ulps
// of that size, missed from 3e6 on; the audit of session 51). The third ray starts inside
// the sphere, whose normal there faced inwards from clip radius 1e14 (the normal's search
// beside the hit looked 2.3e4 away).
TEST_F(QueryTool, AClipRegionFarLargerThanTheSurfaceKeepsItsHits) {
  const double rays[][8] = {{0, 0, -5, 0, 0, 1, 0, 1e300},
                            {3, 0, 0, -1, 0, 0, 0, 10},
                            {0, 0, 0.5, 1, 0, 0, 0, 1e300},
                            {0.3, -5, 0.1, 0, 1, 0, 0, 1e300},
                            {-2, 1.5, 0.25, 1, -0.7, 0.1, 0, 1e300}};
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  char buf[512];
  for (const auto& r : rays) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", r[0], r[1],
                  r[2], r[3], r[4], r[5], r[6], r[7]);
    csv += buf;
  }
  const fs::path file = write("rays.csv", csv);
  for (const std::string clip :
       {"--clip-sphere 1e3", "--clip-sphere 1e7", "--clip-sphere 1e14",
        "--clip-box=-1e14,-1.5,-1.5,1e14,1.5,1.5", "--clip-box=-1e6,-1e6,-2,1e6,1e6,2"})
    for (const bool useFloat : {false, true}) {
      SCOPED_TRACE(clip + (useFloat ? " --float" : ""));
      const RunResult r = run("--surface \"x^2 + y^2 + z^2 - 1\" " + clip +
                              (useFloat ? " --float " : " ") + common(file));
      ASSERT_EQ(r.exitCode, 0) << r.err;
      ASSERT_EQ(r.rows.size(), std::size(rays));
      for (size_t i = 0; i < std::size(rays); ++i) {
        const double t = sphereT(rays[i], rays[i] + 3, 1.0, 0.0);
        ASSERT_GT(t, 0.0);
        EXPECT_EQ(r.rows[i][0], 1.0) << i;
        EXPECT_NEAR(r.rows[i][1], t, (useFloat ? 1e-6 : 1e-14) * t) << i;
        double p[3], dot = 0;
        for (int k = 0; k < 3; ++k) p[k] = rays[i][k] + t * rays[i][3 + k];
        for (int k = 0; k < 3; ++k) dot += r.rows[i][2 + k] * p[k];
        EXPECT_NEAR(dot, 1.0, useFloat ? 1e-6 : 1e-12) << i << ": the normal is the outward p";
      }
    }
}

TEST_F(QueryTool, HitPointsAsOriginsDoNotHitThemselves) {
  // First pass: hits on a torus from outside. Second pass: rays from those hit points
  // (o + t d, as a user computes them from OUT.csv) with tnear = 0, towards the centre
  // and away from it.
  const std::string surface =
      "--surface \"(x^2+y^2+z^2+R^2-r^2)^2 - 4*R^2*(x^2+y^2)\" --param R=1 --param r=0.4 "
      "--clip-sphere 1.6 ";
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  std::vector<std::array<double, 6>> rays;
  for (int i = 0; i < 40; ++i) {
    const double a = 0.37 * i, z = 0.05 * (i % 7) - 0.15;
    std::array<double, 6> ray = {
        4 * std::cos(a), 4 * std::sin(a), 1.0, -std::cos(a) + 0.1 * std::sin(a),
        -std::sin(a),    z - 0.25};
    rays.push_back(ray);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,inf\n", ray[0], ray[1],
                  ray[2], ray[3], ray[4], ray[5]);
    csv += buf;
  }
  const RunResult first = run(surface + common(write("rays.csv", csv)));
  ASSERT_EQ(first.exitCode, 0) << first.err;
  std::string second = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  int hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (first.rows[i][0] != 1.0) continue;
    ++hits;
    const double t = first.rows[i][1];
    const double p[3] = {rays[i][0] + t * rays[i][3], rays[i][1] + t * rays[i][4],
                         rays[i][2] + t * rays[i][5]};
    for (double sign : {-1.0, 1.0}) {  // into the tube and back out along the normal
      char buf[256];
      std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,inf\n", p[0], p[1],
                    p[2], sign * first.rows[i][2], sign * first.rows[i][3],
                    sign * first.rows[i][4]);
      second += buf;
    }
  }
  ASSERT_GT(hits, 20);
  const RunResult r = run(surface + common(write("second.csv", second)));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (size_t i = 0; i < r.rows.size(); ++i) {
    if (r.rows[i][0] == 1.0) {
      EXPECT_GT(r.rows[i][1], 1e-3) << "ray " << i << " found its own origin";
    }
    // Into the tube (even rows): the ray must reach the tube's other wall.
    if (i % 2 == 0) {
      EXPECT_EQ(r.rows[i][0], 1.0) << i;
    }
  }
}

TEST_F(QueryTool, FloatThreadsAndClipBox) {
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  for (int i = 0; i < 200; ++i) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%g,%g,-5,0,0,1,0,inf\n", -1.2 + 0.012 * i, 0.3);
    csv += buf;
  }
  const fs::path rays = write("rays.csv", csv);
  // The clip box removes x > 0.5: those rays miss.
  const std::string base = "--surface \"x^2+y^2+z^2-1\" --clip-box -2,-2,-2,0.5,2,2 ";
  const RunResult one = run(base + common(rays) + " --threads 1");
  ASSERT_EQ(one.exitCode, 0) << one.err;
  const RunResult two = run(base + common(rays) + " --threads 2");
  ASSERT_EQ(two.exitCode, 0) << two.err;
  EXPECT_EQ(one.rows, two.rows);
  const RunResult flt = run(base + common(rays) + " --float");
  ASSERT_EQ(flt.exitCode, 0) << flt.err;
  for (int i = 0; i < 200; ++i) {
    const double x = -1.2 + 0.012 * i, y = 0.3;
    const bool hit = x * x + y * y < 1.0 && x <= 0.5;
    if (std::abs(x * x + y * y - 1.0) < 1e-6 || std::abs(x - 0.5) < 1e-6) continue;
    EXPECT_EQ(one.rows[i][0], hit ? 1.0 : 0.0) << x;
    EXPECT_EQ(flt.rows[i][0], hit ? 1.0 : 0.0) << x;
    if (!hit) continue;
    const double t = 5.0 - std::sqrt(1.0 - x * x - y * y);
    EXPECT_NEAR(one.rows[i][1], t, 1e-13);
    EXPECT_NEAR(flt.rows[i][1], t, 1e-6);
  }
}

// Rays parallel to an inner cell face, just below it (x = -1e-20 beside the face x = 0):
// the owner of a root was the cell whose grid key holds p, and p - gridLo rounds p into
// the cell above, which Embree never visits for such a ray. Every one of them missed the
// unit sphere, in both channels (found by fuzzing, mutated rays of tools.md's CSV).
TEST_F(QueryTool, RaysAlongAnInnerCellFaceHit) {
  const double offsets[] = {-1e-300, -1e-20, -1e-16, -2e-16, 0.0, 1e-20};
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  for (const double e : offsets) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.17g,-5,0.1,0,1,0,0,inf\n0.1,%.17g,-5,0,0,1,0,inf\n", e, e);
    csv += buf;
  }
  const fs::path rays = write("rays.csv", csv);
  const std::string clips[] = {"--clip-box -2,-2,-2,2,2,2", "--clip-sphere 3"};
  for (const std::string& clip : clips)
    for (const std::string channel : {"", " --float"}) {
      const RunResult r = run("--surface \"x^6+y^6+z^6-1\" " + clip + " " + common(rays) + channel);
      ASSERT_EQ(r.exitCode, 0) << r.err;
      ASSERT_EQ(r.rows.size(), 2 * std::size(offsets));
      for (size_t i = 0; i < r.rows.size(); ++i) {
        EXPECT_EQ(r.rows[i][0], 1.0) << clip << channel << ": ray " << i;
        // 0.1^6 beside 1: the hit is at 1 - 1e-6 / 6 from the centre plane, t = 5 - that.
        EXPECT_NEAR(r.rows[i][1], 5.0 - std::pow(1.0 - 1e-6, 1.0 / 6.0), 1e-6) << clip << channel;
      }
    }
}

// A small scene and a large direction: t = 1e-30 / |d| of the hit fell below float's range
// (0 in flush-to-zero threads) and the float channel missed from |d| = 1e8 (found by
// fuzzing, double against --float). Directions beyond 1e17 still miss there: the float
// proxy of such rays has |d| = 2^56 (floatMap), so t underflows for scenes below ~1e-21.
TEST_F(QueryTool, LargeDirectionsHitASmallSphereInBothChannels) {
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  const double lengths[] = {1.0, 1e7, 1e8, 1e10, 1e16, 9e16};
  for (const double l : lengths) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "0,0,0,0,%.17g,0,0,inf\n0,-5e-30,0,0,%.17g,0,0,inf\n", l, l);
    csv += buf;
  }
  const fs::path rays = write("rays.csv", csv);
  for (const std::string channel : {"", " --float"}) {
    const RunResult r =
        run("--surface \"x^2+y^2+z^2-1e-60\" --clip-sphere 2e-30 " + common(rays) + channel);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(r.rows.size(), 2 * std::size(lengths));
    for (size_t i = 0; i < r.rows.size(); ++i) {
      const double l = lengths[i / 2], t = (i % 2 == 0 ? 1e-30 : 4e-30) / l;
      EXPECT_EQ(r.rows[i][0], 1.0) << channel << ": |d| = " << l;
      EXPECT_NEAR(r.rows[i][1], t, (channel.empty() ? 1e-12 : 1e-6) * t)
          << channel << ": |d| = " << l;
    }
  }
}

// Rays from 2^66 to 2^1000 radii and from (-1e308, -1e308, -1e308), each exactly
// through the centre of the unit sphere (o = -2^k d, exact in double), in random
// directions: each must hit at t = |o| / |d| - 1 / |d| in both channels. (From ~2^50
// scene sizes the float proxy's per-axis box crossings round apart and 14-57 % of such
// rays were refused as missing the scene; the diagonal 1e308 ray's origin failed a
// finiteness test by a sum that overflows, and the double channel's re-basing overflowed
// in dot(o, d).)
TEST_F(QueryTool, FarOriginsThroughTheCentreHit) {
  std::mt19937_64 rng(23);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> length(0.5, 2.0);
  struct Ray {
    double o[3], d[3], t;
  };
  std::vector<Ray> rays;
  for (const int e : {66, 200, 600, 1000})
    for (int i = 0; i < 25; ++i) {
      Ray r{};
      double n = 0;
      for (double& c : r.d) {
        c = normal(rng);
        n += c * c;
      }
      const double scale = length(rng) / std::sqrt(n), k = std::ldexp(1.0, e);
      for (int a = 0; a < 3; ++a) r.d[a] *= scale, r.o[a] = -k * r.d[a];
      r.t = k;  // k - 1 / |d|, which rounds to k from 2^66 on
      rays.push_back(r);
    }
  rays.push_back({{-1e308, -1e308, -1e308}, {1, 1, 1}, 1e308});
  rays.push_back({{-1e308, -1e308, -1e308}, {1e300, 1e300, 1e300}, 1e8});
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  char buf[512];
  for (const Ray& r : rays) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,inf\n", r.o[0], r.o[1],
                  r.o[2], r.d[0], r.d[1], r.d[2]);
    csv += buf;
  }
  const fs::path file = write("far.csv", csv);
  for (const std::string mode : {"", " --float"}) {
    const RunResult r = run("--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 " + common(file) + mode);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(r.rows.size(), rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      const Ray& ray = rays[i];
      ASSERT_EQ(r.rows[i][0], 1.0) << "ray " << i << mode << " from |o| = " << std::abs(ray.o[0]);
      EXPECT_NEAR(r.rows[i][1], ray.t, 4e-16 * ray.t) << "ray " << i << mode;
      // The normal at the entry point is -d / |d| (d scaled first: 1e300 has no square).
      const double m = std::max({std::abs(ray.d[0]), std::abs(ray.d[1]), std::abs(ray.d[2])});
      const double u[3] = {ray.d[0] / m, ray.d[1] / m, ray.d[2] / m};
      const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(r.rows[i][2 + a], -u[a] / len, 1e-6) << "ray " << i << mode;
    }
  }
}

// (x + 1)^N - 1 = 0 is the planes x = 0 and (even N) x = -2. Seen along -x from x = 3
// the first root is x = 0, t = 3 (simple, slope N). At degree 33-40 the ray polynomial's
// noise bound exceeds |g| near the far end of the clip span, and the solver reported the
// span's far end (t = 4.5 in the clip sphere of radius 1.5, where f = 0.5^N - 1) instead.
TEST_F(QueryTool, HighDegreeRootBeforeANoiseLevelSpanEnd) {
  const fs::path rays = write("rays.csv",
                              "ox,oy,oz,dx,dy,dz,tnear,tfar\n3,0,0,-1,0,0,0,inf\n"
                              "3,0.3,-0.2,-1,0,0,0,inf\n3,0,0,-2,0,0,0,inf\n");
  for (const int n : {33, 35, 40})
    for (const char* radius : {"1.5", "2"}) {
      const RunResult r = run("--surface \"(x+1)^" + std::to_string(n) + " - 1\" --clip-sphere " +
                              radius + " " + common(rays));
      ASSERT_EQ(r.exitCode, 0) << r.err;
      ASSERT_EQ(r.rows.size(), 3u);
      for (size_t i = 0; i < 3; ++i) {
        const std::string what =
            "N = " + std::to_string(n) + ", R = " + radius + ", ray " + std::to_string(i);
        ASSERT_EQ(r.rows[i][0], 1.0) << what;
        EXPECT_NEAR(r.rows[i][1], i == 2 ? 1.5 : 3.0, 1e-12) << what;
        EXPECT_NEAR(r.rows[i][2], 1.0, 1e-12) << what;  // grad = N (x + 1)^(N-1) e_x
      }
    }
}

// Chmutov's surface T16(x) + T16(y) + T16(z) + 1 = 0 (as the gallery writes it: Chebyshev
// polynomials expanded, coefficients up to 2^18 that cancel to O(1) on the surface) in an
// off-centre clip box. Its ray polynomials were expanded about the ray's point closest to
// the box centre (-2.05, 0.24, -0.41), where the expansion's terms are ~1e8 times the
// values near the surface: hits 2e-3 box radii off, normals 15-50 degrees off, on 4 of 349
// well-conditioned rays of a random sweep (those 4 first, then random rays). Reference:
// the closed form T16(x) = cos(16 acos x) (cosh(16 acosh |x|) beyond 1) along the ray in
// long double, first sign change on a grid of the span refined by bisection.
TEST_F(QueryTool, OffCentreClipBoxChmutov16AgainstClosedForm) {
  const double lo[3] = {-3.35498, -1.40295, -1.52329}, hi[3] = {-0.739214, 1.88969, 0.696178};
  const char* clip = "-3.35498,-1.40295,-1.52329,-0.739214,1.88969,0.696178";
  const double coeff[9] = {1,       -128,   2688,    -21504, 84480,
                           -180224, 212992, -131072, 32768};  // T16, x^0..x^16
  std::string equation = "1";
  for (const char* v : {"x", "y", "z"})
    for (int k = 0; k <= 8; ++k) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " %+.17g*%s^%d", coeff[k], v, 2 * k);
      equation += buf;
    }
  auto t16 = [](long double x) {
    const long double a = std::fabs(x);
    return a <= 1 ? std::cos(16 * std::acos(x)) : std::cosh(16 * std::acosh(a));
  };
  struct Ray {
    double o[3], d[3], tfar;
  };
  std::vector<Ray> rays = {
      {{-18048288286.445034, -6138698963.579716, -10563861332.92758},
       {3.0639524684143566, 1.0421310623559232, 1.793365027028933},
       INFINITY},
      {{21.49556168133346, -3.024148533112233, 2.236600898192007},
       {-99197915.22836436, 9192474.250292402, -8675945.568291007},
       INFINITY},
      {{2.0957740088781334, 0.960279507817646, 1.895940248754072},
       {-0.9120652048647508, -0.00770854294913458, -0.40997273133785544},
       4.550325688126394},
      {{-6.802067887332539, 0.6572435832399665, 0.26129159927737333}, {1e-08, 0.0, 0.0}, INFINITY}};
  std::mt19937_64 rng(176);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  while (rays.size() < 300) {
    Ray r{};
    double n = 0, target[3];
    for (int a = 0; a < 3; ++a)
      target[a] = lo[a] + unit(rng) * (hi[a] - lo[a]), r.d[a] = normal(rng), n += r.d[a] * r.d[a];
    for (int a = 0; a < 3; ++a) r.o[a] = target[a] - 6.0 * r.d[a] / std::sqrt(n);
    for (int a = 0; a < 3; ++a) r.d[a] = target[a] - r.o[a];
    r.tfar = INFINITY;
    rays.push_back(r);
  }
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  for (const Ray& r : rays) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,%.17g\n", r.o[0], r.o[1],
                  r.o[2], r.d[0], r.d[1], r.d[2], r.tfar);
    csv += buf;
  }
  const RunResult out = run("--surface \"" + equation + "\" --clip-box " + clip + " " +
                            common(write("rays.csv", csv)));
  ASSERT_EQ(out.exitCode, 0) << out.err;
  ASSERT_EQ(out.rows.size(), rays.size());
  double boxRadius = 0;
  for (int a = 0; a < 3; ++a) boxRadius += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  boxRadius = std::sqrt(boxRadius);
  int checked = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& r = rays[i];
    long double t0 = 0, t1 = r.tfar;  // the slab span
    for (int a = 0; a < 3; ++a) {
      if (r.d[a] == 0) continue;
      long double ta = ((long double)lo[a] - r.o[a]) / r.d[a],
                  tb = ((long double)hi[a] - r.o[a]) / r.d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    auto f = [&](long double t) {
      long double s = 1;
      for (int a = 0; a < 3; ++a) s += t16(r.o[a] + t * r.d[a]);
      return s;
    };
    if (!(t0 < t1)) continue;
    // First sign change on the grid; rays with a near-tangency before it (a grid value
    // within 1e-3 of 0 without a sign change) or a root near a span end are skipped.
    const int steps = 20000;
    long double a = t0, fa = f(a), tRef = -1;
    bool doubtful = std::fabs(fa) < 1e-3;
    for (int k = 1; k <= steps && tRef < 0 && !doubtful; ++k) {
      long double b = t0 + (t1 - t0) * k / steps;
      const long double fb = f(b);
      if ((fa < 0) != (fb < 0)) {
        for (int it = 0; it < 100; ++it) {
          const long double m = (a + b) / 2, fm = f(m);
          ((fm < 0) == (fa < 0) ? a : b) = m;
        }
        tRef = (a + b) / 2;
        doubtful = k == steps;
      } else if (std::fabs(fb) < 1e-3) {
        doubtful = true;
      }
      a = b, fa = fb;
    }
    if (doubtful) continue;
    const double dLen = std::sqrt(r.d[0] * r.d[0] + r.d[1] * r.d[1] + r.d[2] * r.d[2]);
    ++checked;
    ASSERT_EQ(out.rows[i][0], tRef >= 0 ? 1.0 : 0.0) << "ray " << i;
    if (tRef < 0) continue;
    EXPECT_NEAR(out.rows[i][1], (double)tRef, 1e-9 * boxRadius / dLen + 1e-15 * (double)tRef)
        << "ray " << i;
  }
  EXPECT_GT(checked, 200);
}

// Directions whose length overflows double (components near 1e308 on two or three axes):
// the float proxy's map divided by |d| = inf and refused the ray, so it missed in the
// double channel although its origin o = -d is finite and the line crosses the centre of
// the unit sphere at t = 1; the hit is at t = 1 - 1 / |d|, which rounds to 1. The float
// channel missed them too until its map measured the moves in the parameter of d scaled
// by a power of two instead of arc lengths from o, which overflowed
// (EmbreeHits.DirectionsAndOriginsNear1e308HitTheEntry).
TEST_F(QueryTool, DirectionsWhoseLengthOverflowsHitInBothChannels) {
  const double d[][3] = {{1.7e308, 1.7e308, 1.7e308},
                         {1.7e308, -1.7e308, 0},
                         {1e308, 1.5e308, -1.2e308},
                         {-1.79e308, 1.79e308, 1e300}};
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  for (const auto& v : d) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,inf\n", -v[0], -v[1],
                  -v[2], v[0], v[1], v[2]);
    csv += buf;
  }
  const fs::path rays = write("rays.csv", csv);
  for (const std::string mode : {"", " --float"}) {
    const RunResult r = run("--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 " + common(rays) + mode);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(r.rows.size(), std::size(d));
    for (size_t i = 0; i < std::size(d); ++i) {
      ASSERT_EQ(r.rows[i][0], 1.0) << "ray " << i << mode;
      EXPECT_EQ(r.rows[i][1], 1.0) << "ray " << i << mode;
      // The normal at the entry point is -d / |d|, with d scaled first.
      const double m = std::max({std::abs(d[i][0]), std::abs(d[i][1]), std::abs(d[i][2])});
      const double u[3] = {d[i][0] / m, d[i][1] / m, d[i][2] / m};
      const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      const double tol = mode.empty() ? 1e-12 : 1e-6;  // the float channel's Ng is float
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(r.rows[i][2 + a], -u[a] / len, tol) << "ray " << i << mode;
    }
  }
}

// As above, from hit points of rays that started 5-20 clip radii away, on a thin
// cylinder and a sphere: their o + t d is off the surface by up to gamma(3) (|o| + |t d|),
// 40 ulps of the point, and with no column for that in IN.csv such rays found their own
// origin (t = 2.5e-15 and 1.2e-13 leaving x^2 + y^2 = 0.140001, seen from 10 radii).
// Rays into the solid must reach its far wall (closed form, long double).
// ---- Rays leaving hit points ----------------------------------------------------------
using Ray6 = std::array<double, 6>;  // ox, oy, oz, dx, dy, dz

// `count` rays from distances in [near, far) towards random points within 0.4 of the
// centre (appended to `rays`).
void aimedRays(std::mt19937_64& rng, size_t count, double near, double far,
               std::vector<Ray6>& rays) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(-1.0, 1.0), dist(near, far);
  while (rays.size() < count) {
    double u[3], n = 0, target[3];
    for (int a = 0; a < 3; ++a) u[a] = normal(rng), n += u[a] * u[a], target[a] = 0.4 * unit(rng);
    const double r = dist(rng) / std::sqrt(n);
    rays.push_back(
        {target[0] + r * u[0], target[1] + r * u[1], target[2] + r * u[2], -u[0], -u[1], -u[2]});
  }
}

// IN.csv of rays on [0, inf), with an org_error column when `orgErrors` is given.
std::string raysCsv(const std::vector<Ray6>& rays, const std::vector<double>* orgErrors = nullptr) {
  std::string csv =
      orgErrors ? "org_error,ox,oy,oz,dx,dy,dz,tnear,tfar\n" : "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  char buf[512];
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray6& r = rays[i];
    if (orgErrors) csv += (std::snprintf(buf, sizeof buf, "%.17g,", (*orgErrors)[i]), buf);
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,inf\n", r[0], r[1], r[2],
                  r[3], r[4], r[5]);
    csv += buf;
  }
  return csv;
}

// From each hit of `first` (the rays `rays`), two rays from the hit point o + t d along
// the normal: into the solid (even index) and away from it (odd). orgErrors: each hit
// point's bound gamma(3) (|o| + |t d|) (pbrt-v4 Sec. 6.8.6).
std::vector<Ray6> leavingRays(const std::vector<Ray6>& rays, const RunResult& first,
                              std::vector<double>& orgErrors) {
  std::vector<Ray6> leaving;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (first.rows[i][0] != 1.0) continue;
    const double t = first.rows[i][1];
    const Ray6& r = rays[i];
    const double p[3] = {r[0] + t * r[3], r[1] + t * r[4], r[2] + t * r[5]};
    const double err = 3 * 0x1p-53 / (1 - 3 * 0x1p-53) *
                       (std::hypot(r[0], r[1], r[2]) + std::abs(t) * std::hypot(r[3], r[4], r[5]));
    for (double sign : {-1.0, 1.0}) {
      leaving.push_back({p[0], p[1], p[2], sign * first.rows[i][2], sign * first.rows[i][3],
                         sign * first.rows[i][4]});
      orgErrors.push_back(err);
    }
  }
  return leaving;
}

// Far root along a ray into the solid of sum_{j < axes} x_j^2 = c (long double).
double farRoot(const Ray6& l, int axes, double c) {
  long double a = 0, b = 0, k = -(long double)c;
  for (int j = 0; j < axes; ++j)
    a += (long double)l[3 + j] * l[3 + j], b += 2.0L * l[j] * l[3 + j],
        k += (long double)l[j] * l[j];
  return (double)((-b + std::sqrt(b * b - 4 * a * k)) / (2 * a));
}

// Rays leaving hit points of rays from 10-40 radii (within the 32 the tool assumes
// without org_error): none finds its own origin, those into the solid hit its far side.
TEST_F(QueryTool, HitPointsOfRaysFromFarAwayDoNotHitThemselves) {
  struct Case {
    const char* surface;
    bool sphere;  // x^2 + y^2 + z^2 = c, else x^2 + y^2 = c
    double c;
  };
  for (const Case& k :
       {Case{"(x^2+y^2-0.14) - 1e-6", false, 0.14 + 1e-6}, Case{"x^2+y^2+z^2 - 0.3", true, 0.3}}) {
    std::mt19937_64 rng(84);
    std::vector<Ray6> rays = {{-19.843460565145342, -1.250984248354485, 1.1583122124118925,
                               0.996245764170719, 0.07760926223297725, -0.038355961564706484}};
    aimedRays(rng, 300, 10.0, 40.0, rays);
    const std::string surface = std::string("--surface \"") + k.surface + "\" --clip-sphere 2 ";
    const RunResult first = run(surface + common(write("rays.csv", raysCsv(rays))));
    ASSERT_EQ(first.exitCode, 0) << first.err;
    std::vector<double> orgErrors;
    const std::vector<Ray6> leaving = leavingRays(rays, first, orgErrors);
    ASSERT_GT(leaving.size(), 100u) << k.surface;
    const RunResult r = run(surface + common(write("second.csv", raysCsv(leaving))));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(r.rows.size(), leaving.size());
    for (size_t i = 0; i < leaving.size(); ++i) {
      if (r.rows[i][0] == 1.0) {
        EXPECT_GT(r.rows[i][1], 1e-3) << k.surface << ": ray " << i << " found its own origin";
      }
      if (i % 2 != 0) continue;
      ASSERT_EQ(r.rows[i][0], 1.0) << k.surface << ": ray " << i;
      EXPECT_NEAR(r.rows[i][1], farRoot(leaving[i], k.sphere ? 3 : 2, k.c), 1e-12)
          << k.surface << ": ray " << i;
    }
  }
}

// As above in a clip box centred far from the world origin, at (1e3, 1e3, 0): the origins'
// default bound is measured from the clip centre (tools.md: gamma(3) (|o - c| + 64 R_s) for
// an origin within 4 clip radii of it), so hit points 1e3 from the world origin keep it.
// The planes z = +-1 (f = z^2 - 1, exact wherever x and y lie): a ray into the slab from
// either plane along the normal (0, 0, -+1) meets the other one at t = 2.
TEST_F(QueryTool, HitPointsInAnOffCentreClipBoxDoNotHitThemselves) {
  std::mt19937_64 rng(84);
  std::vector<Ray6> rays;
  aimedRays(rng, 2000, 10.0, 40.0, rays);
  for (Ray6& r : rays) r[0] += 1e3, r[1] += 1e3;
  const std::string surface = "--surface \"z^2-1\" --clip-box 998.5,998.5,-1.5,1001.5,1001.5,1.5 ";
  const RunResult first = run(surface + common(write("rays.csv", raysCsv(rays))));
  ASSERT_EQ(first.exitCode, 0) << first.err;
  std::vector<double> orgErrors;
  const std::vector<Ray6> leaving = leavingRays(rays, first, orgErrors);
  ASSERT_GT(leaving.size(), 300u);
  const RunResult r = run(surface + common(write("second.csv", raysCsv(leaving))));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_EQ(r.rows.size(), leaving.size());
  for (size_t i = 0; i < leaving.size(); ++i) {
    if (r.rows[i][0] == 1.0) {
      EXPECT_GT(r.rows[i][1], 1e-3) << "ray " << i << " found its own origin";
    }
    if (i % 2 != 0) continue;
    ASSERT_EQ(r.rows[i][0], 1.0) << "ray " << i;
    EXPECT_NEAR(r.rows[i][1], 2.0, 1e-12) << "ray " << i;
  }
}

// The same from 300-3000 radii: beyond the tool's assumption a leaving ray can find its
// own origin; with each origin's bound in the column org_error none does, and the rays
// into the solid hit its far side.
TEST_F(QueryTool, OriginErrorsFromTheColumnStopSelfHitsOfFarRays) {
  std::mt19937_64 rng(29);
  std::vector<Ray6> rays;
  aimedRays(rng, 400, 300.0, 3000.0, rays);
  const std::string surface = "--surface \"x^2+y^2+z^2-0.3\" --clip-sphere 2 ";
  const RunResult first = run(surface + common(write("far.csv", raysCsv(rays))));
  ASSERT_EQ(first.exitCode, 0) << first.err;
  std::vector<double> orgErrors;
  const std::vector<Ray6> leaving = leavingRays(rays, first, orgErrors);
  ASSERT_GT(leaving.size(), 300u);
  auto selfHits = [&](const RunResult& r) {
    int n = 0;
    for (size_t i = 0; i < leaving.size(); ++i) n += r.rows[i][0] == 1.0 && r.rows[i][1] <= 1e-3;
    return n;
  };
  const RunResult with = run(surface + common(write("with.csv", raysCsv(leaving, &orgErrors))));
  ASSERT_EQ(with.exitCode, 0) << with.err;
  ASSERT_EQ(with.rows.size(), leaving.size());
  EXPECT_EQ(selfHits(with), 0);
  for (size_t i = 0; i < leaving.size(); i += 2) {
    ASSERT_EQ(with.rows[i][0], 1.0) << "ray " << i;
    EXPECT_NEAR(with.rows[i][1], farRoot(leaving[i], 3, 0.3), 1e-9) << "ray " << i;
  }
  // Without the column the tool's assumption is too small for these origins and some find
  // themselves (so the column, not luck, made the difference above).
  const RunResult without = run(surface + common(write("without.csv", raysCsv(leaving))));
  ASSERT_EQ(without.exitCode, 0) << without.err;
  EXPECT_GT(selfHits(without), 0);
}

// Embree's float ray has no origin error: with --float a non-zero org_error was read and
// silently ignored. Refused before tracing (OUT is not written), naming the ray, the column
// and the option; zeros (the float ray's own assumption covers them) and the double
// channel pass.
TEST_F(QueryTool, FloatRefusesANonZeroOrgError) {
  const std::string surface = "--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 ";
  const std::string header = "ox,oy,oz,dx,dy,dz,tnear,tfar,org_error\n";
  const fs::path given =
      write("given.csv", header + "0,0,-5,0,0,1,0,inf,0\n0,0,-5,0,0,1,0,inf,2e-14\n");
  const RunResult refused = run(surface + common(given) + " --float");
  EXPECT_EQ(refused.exitCode, 2) << refused.err;
  EXPECT_NE(refused.err.find("algray-query: --float: ray 2 has org_error 2e-14, which Embree's "
                             "float rays cannot carry"),
            std::string::npos)
      << refused.err;
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
  EXPECT_EQ(refused.err.find("rays/s"), std::string::npos) << refused.err;  // not traced
  const RunResult doubleChannel = run(surface + common(given));
  EXPECT_EQ(doubleChannel.exitCode, 0) << doubleChannel.err;
  ASSERT_EQ(doubleChannel.rows.size(), 2u);
  EXPECT_EQ(doubleChannel.rows[1][1], 4.0);
  const RunResult zeros =
      run(surface + common(write("zeros.csv", header + "0,0,-5,0,0,1,0,inf,0\n")) + " --float");
  EXPECT_EQ(zeros.exitCode, 0) << zeros.err;
  ASSERT_EQ(zeros.rows.size(), 1u);
  EXPECT_NEAR(zeros.rows[0][1], 4.0, 1e-6);
}

// A gallery name as --surface traces that surface in its own clip sphere (or the one given):
// the same hits, bit for bit, as its polynomial written out with that sphere.
TEST_F(QueryTool, GalleryNamesTraceTheGallerySurface) {
  std::string csv = "ox,oy,oz,dx,dy,dz,tnear,tfar\n";
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  char buf[256];
  for (int i = 0; i < 200; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,4,%.17g,%.17g,-1,0,inf\n", 2 * u(rng), 2 * u(rng),
                  0.3 * u(rng), 0.3 * u(rng));
    csv += buf;
  }
  const fs::path rays = write("rays.csv", csv);
  for (const char* name : {"barth-sextic", "Chmutov_8", "torus"}) {
    SCOPED_TRACE(name);
    const algray::GallerySurface* g = algray::findGallerySurface(name);
    ASSERT_NE(g, nullptr);
    const RunResult byName = run(std::string("--surface ") + name + " " + common(rays));
    ASSERT_EQ(byName.exitCode, 0) << byName.err;
    std::snprintf(buf, sizeof buf, " --clip-sphere %.17g ", g->clipRadius);
    const RunResult written =
        run("--surface \"" + g->build().toString() + "\"" + buf + common(rays));
    ASSERT_EQ(written.exitCode, 0) << written.err;
    ASSERT_EQ(byName.rows.size(), 200u);
    int hits = 0;
    for (size_t i = 0; i < byName.rows.size(); ++i) {
      EXPECT_EQ(byName.rows[i], written.rows[i]) << "ray " << i;
      hits += byName.rows[i][0] != 0.0;
    }
    EXPECT_GT(hits, 20);
    // A smaller clip sphere given on the command line is the one traced.
    const RunResult clipped =
        run(std::string("--surface ") + name + " --clip-sphere 0.01 " + common(rays));
    ASSERT_EQ(clipped.exitCode, 0) << clipped.err;
    for (const auto& row : clipped.rows) EXPECT_EQ(row[0], 0.0);
  }
}

// A surface with no point in the clip region is traced (every ray misses, exit code 0) with
// a warning; one the clip region holds gets none.
TEST_F(QueryTool, ASurfaceOutsideTheClipRegionIsNamed) {
  const fs::path rays = write("rays.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-30,0,0,1,0,inf\n");
  const std::string warning = "warning: no point of the surface lies in the clip region";
  const RunResult outside = run("--surface \"x^2+y^2+z^2-100\" --clip-sphere 2 " + common(rays));
  EXPECT_EQ(outside.exitCode, 0) << outside.err;
  EXPECT_NE(outside.err.find(warning), std::string::npos) << outside.err;
  ASSERT_EQ(outside.rows.size(), 1u);
  EXPECT_EQ(outside.rows[0][0], 0.0);
  const RunResult inside = run("--surface \"x^2+y^2+z^2-100\" --clip-sphere 20 " + common(rays));
  EXPECT_EQ(inside.exitCode, 0) << inside.err;
  EXPECT_EQ(inside.err.find(warning), std::string::npos) << inside.err;
  ASSERT_EQ(inside.rows.size(), 1u);
  EXPECT_EQ(inside.rows[0][0], 1.0);
  EXPECT_EQ(inside.rows[0][1], 20.0);  // the sphere of radius 10 from z = -30
}

// A torus written about x = 1e4 expands to coefficients whose rounding holds no torus: f is
// within its own evaluation bound through its whole clip box, and the rays hit rounding
// noise (session 54's audit: t = 4.8 at the cell's entry where the torus is at 4.6). The
// tool says so; the same torus about x = 1e2 gets no warning, nor does Barth's sextic.
TEST_F(QueryTool, ASurfaceLostInRoundingIsNamed) {
  const std::string warning = "f is within its own rounding error at";
  for (const char* centre : {"1e4", "1e2"}) {
    const fs::path rays = write(
        "rays.csv", std::string("ox,oy,oz,dx,dy,dz,tnear,tfar\n") + centre + ",-6,0,0,1,0,0,inf\n");
    const double c = std::stod(centre);
    const std::string torus =
        std::string("((x-") + centre + ")^2+y^2+z^2+0.84)^2-4*((x-" + centre + ")^2+y^2)";
    const RunResult r = run("--surface \"" + torus + "\" --clip-box " + std::to_string(c - 1.6) +
                            ",-1.6,-1.6," + std::to_string(c + 1.6) + ",1.6,1.6 " + common(rays));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find(warning) != std::string::npos, std::string(centre) == "1e4")
        << centre << ": " << r.err;
  }
  const fs::path rays = write("rays.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,-6,0,0,1,0,0,inf\n");
  const RunResult barth = run("--surface barth-sextic " + common(rays));
  EXPECT_EQ(barth.exitCode, 0) << barth.err;
  EXPECT_EQ(barth.err.find(warning), std::string::npos) << barth.err;
}

// The warning judges f as the library traces it, scaled by a power of two to a largest
// coefficient near 1: 1e300 (x^2+y^2+z^2-1) in a clip sphere of 1e10 is the unit sphere
// exactly (its unscaled values overflow from |p| ~ 1e4 on, which read as "within its
// rounding error at 100 %"). Subnormal coefficients keep the warning: 1e-320 (... - 0.7)
// rounds -0.7e-320 to a multiple of 2^-1074 (relative error up to 3.5e-4), a sphere
// measurably smaller than sqrt(0.7).
TEST_F(QueryTool, TheRoundingWarningIgnoresAScaleAndKeepsLostDigits) {
  const std::string warning = "f is within its own rounding error at";
  const fs::path rays = write("rays.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,5,0,0,-1,0,inf\n");
  const RunResult scaled =
      run("--surface \"1e300*(x^2+y^2+z^2-1)\" --clip-sphere 1e10 " + common(rays));
  EXPECT_EQ(scaled.exitCode, 0) << scaled.err;
  EXPECT_EQ(scaled.err.find(warning), std::string::npos) << scaled.err;
  ASSERT_EQ(scaled.rows.size(), 1u);
  EXPECT_EQ(scaled.rows[0][1], 4.0);  // the unit sphere from z = 5
  const RunResult lost =
      run("--surface \"1e-320*(x^2+y^2+z^2-0.7)\" --clip-sphere 2 " + common(rays));
  EXPECT_EQ(lost.exitCode, 0) << lost.err;
  EXPECT_NE(lost.err.find(warning), std::string::npos) << lost.err;
}

// A clip box beyond the plugin's range is refused by the plugin, which names its size: the
// tool's own check of the rays' far t overflowed on the box's radius first and blamed the
// rays' directions ("the direction is so short ...").
TEST_F(QueryTool, AClipBoxBeyondThePluginsRangeIsNamed) {
  const fs::path rays = write("rays.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-3,0,0,1,0,inf\n");
  for (const char* box : {"-1e200,-1,-1,1e200,1,1", "-1e308,-1,-1,1.7e308,1,1"}) {
    const RunResult r =
        run("--surface \"x^2+y^2+z^2-1\" --clip-box " + std::string(box) + " " + common(rays));
    EXPECT_EQ(r.exitCode, 2) << box;
    EXPECT_NE(r.err.find("the clip region's size"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("direction"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("is inf"), std::string::npos) << r.err;  // beyond double: no size
  }
}

// A clip region too small or large for double (or its size to the degree) is refused with
// what the tool's user can change: the library's remedy, its transform, is no option here
// (--clip-sphere 1e-300 was told to "undo it by the transform").
TEST_F(QueryTool, AScaleBeyondDoubleNamesTheToolsOptions) {
  const fs::path rays = write("rays.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-3,0,0,1,0,inf\n");
  struct Case {
    std::string args, option, problem;
  };
  const std::vector<Case> cases = {
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere 1e-300 ", "--clip-sphere",
       "the clip region's size in object space is 1e-300, outside 1e-100 .. 1e100"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box 0,0,0,1e200,1e200,1e200 ", "--clip-box",
       "outside 1e-100 .. 1e100"},
      {"--surface \"x^40+y^40+z^40-1\" --clip-sphere 1e7 ", "--clip-sphere",
       "to the polynomial's degree (40) is about 1e280"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args + common(rays));
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.find("transform"), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find("algray-query: --surface, " + c.option + ": "), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find(c.problem), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(": write --surface in units of about the surface's size, and " + c.option +
                         " and the rays in the same units (--rays: every column but tnear "
                         "and tfar"),
              std::string::npos)
        << r.err;
  }
}

// OUT is opened (truncated) only once every hit is known: a surface the plugin refuses
// (after the rays were read and OUT opened) left OUT empty, and with --out naming the rays
// file the input was lost.
TEST_F(QueryTool, AFailedRunLeavesTheOutputFileAsItWas) {
  const std::string raysText = "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n";
  const fs::path rays = write("rays.csv", raysText);
  auto contents = [](const fs::path& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string sameFile = "--rays " + rays.string() + " --out " + rays.string();
  for (const std::string& refused : {std::string("--surface x --clip-sphere 1e300 "),
                                     std::string("--surface 1 --clip-sphere 2 ")}) {
    const RunResult r = run(refused + sameFile);
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(contents(rays), raysText) << refused;
  }
  // A successful run replaces it.
  const RunResult ok = run("--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 " + sameFile);
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_EQ(contents(rays).rfind("hit,t,nx,ny,nz\n1,4,", 0), 0u) << contents(rays);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  // OUT is written in place: a symbolic link (also a dangling one) keeps pointing at its
  // target, which gets the hits, a hard link sees them, and OUT that is no regular file
  // (/dev/null here; /dev/stdout, a pipe) is written as it is.
  write("rays.csv", raysText);
  write("real.csv", "old\n");
  const std::string sphere = "--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 --rays " + rays.string();
  const std::string hits = "hit,t,nx,ny,nz\n1,4,";
  for (const char* target : {"real.csv", "missing.csv"}) {
    fs::remove(dir / "link.csv");
    fs::remove(dir / "missing.csv");
    fs::create_symlink(target, dir / "link.csv");
    const RunResult linked = run(sphere + " --out " + (dir / "link.csv").string());
    EXPECT_EQ(linked.exitCode, 0) << linked.err;
    EXPECT_TRUE(fs::is_symlink(dir / "link.csv")) << target;
    EXPECT_EQ(contents(dir / target).rfind(hits, 0), 0u) << target;
  }
  write("keep.csv", "old\n");
  fs::remove(dir / "hard.csv");
  fs::create_hard_link(dir / "keep.csv", dir / "hard.csv");
  const RunResult hard = run(sphere + " --out " + (dir / "keep.csv").string());
  EXPECT_EQ(hard.exitCode, 0) << hard.err;
  EXPECT_EQ(contents(dir / "hard.csv").rfind(hits, 0), 0u);
  // (Through a link of the test's own: were it replaced, the link would be, not /dev/null.)
  fs::remove(dir / "null.csv");
  fs::create_symlink("/dev/null", dir / "null.csv");
  const RunResult null = run(sphere + " --out " + (dir / "null.csv").string());
  EXPECT_EQ(null.exitCode, 0) << null.err;
  EXPECT_TRUE(fs::is_symlink(dir / "null.csv"));
  EXPECT_TRUE(fs::is_character_file(dir / "null.csv"));
  // A directory as OUT is named before any tracing.
  write("rays.csv", raysText);
  fs::create_directories(dir / "outdir");
  const RunResult d = run("--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 --rays " + rays.string() +
                          " --out " + (dir / "outdir").string());
  EXPECT_EQ(d.exitCode, 2);
  EXPECT_NE(d.err.find("is a directory"), std::string::npos) << d.err;
}

// A surface of size 1e-30 and degree 8, x^8 + y^8 + z^8 = r^8 (r = 1e-30): its gradient
// 8 (x^7, y^7, z^7) is about 1e-209, whose square underflows to 0, so the normal is scaled
// before it is normalised; it must come out as the unit normal of the closed form. In
// units of r the hit point is (u, v, -w), w = (1 - u^8 - v^8)^(1/8), at t = (5 - w) r
// from z = -5 r along +z, and the normal is (u^7, v^7, -w^7) normalised.
TEST_F(QueryTool, NormalsOfATinyHighDegreeSurfaceAreUnit) {
  const fs::path rays = write("rays.csv",
                              "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5e-30,0,0,1,0,inf\n"
                              "1e-31,2e-31,-5e-30,0,0,1,0,inf\n");
  const RunResult r = run("--surface \"x^8+y^8+z^8-1e-240\" --clip-sphere 2e-30 " + common(rays));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_EQ(r.rows.size(), 2u);
  const double uv[2][2] = {{0, 0}, {0.1, 0.2}};
  for (size_t i = 0; i < 2; ++i) {
    const long double u = uv[i][0], v = uv[i][1];
    const long double w = std::pow(1 - std::pow(u, 8) - std::pow(v, 8), 1.0L / 8);
    const long double n[3] = {std::pow(u, 7), std::pow(v, 7), -std::pow(w, 7)};
    const long double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    ASSERT_EQ(r.rows[i][0], 1.0) << "ray " << i;
    EXPECT_NEAR(r.rows[i][1], (double)((5 - w) * 1e-30L), 1e-12 * 4e-30) << "ray " << i;
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(r.rows[i][2 + a], (double)(n[a] / len), 1e-12) << "ray " << i << ", axis " << a;
  }
}

// --float traces Embree's float rays, whose origin is uncertain by 16 float ulps of its
// distance plus the scene's radius (README: at least 16 * 2^-24 * 1 = 9.5e-7 here): a
// root 1e-7 from the origin is the origin's own, so a ray leaving the unit sphere from
// 1e-7 inside it meets nothing, and one into the sphere its far side. Double rays with
// org_error 0 find the root at t = 1 - |o| (exact in double: Sterbenz), and the far side
// at 1 + |o|.
TEST_F(QueryTool, FloatRaysTakeARootWithinTheirOriginsRoundingForTheirOwn) {
  const double o = 0.9999999;
  const fs::path rays = write("rays.csv",
                              "ox,oy,oz,dx,dy,dz,tnear,tfar,org_error\n"
                              "0,0,0.9999999,0,0,1,0,inf,0\n"
                              "0,-0.9999999,0,0,-1,0,0,inf,0\n"
                              "0,0,0.9999999,0,0,-1,0,inf,0\n");
  const std::string sphere = "--surface \"x^2+y^2+z^2-1\" --clip-sphere 1.5 ";
  const RunResult twice = run(sphere + common(rays));
  ASSERT_EQ(twice.exitCode, 0) << twice.err;
  ASSERT_EQ(twice.rows.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    ASSERT_EQ(twice.rows[i][0], 1.0) << "ray " << i;
    EXPECT_NEAR(twice.rows[i][1], i < 2 ? 1.0 - o : 1.0 + o, 1e-15) << "ray " << i;
  }
  const RunResult single = run(sphere + common(rays) + " --float");
  ASSERT_EQ(single.exitCode, 0) << single.err;
  ASSERT_EQ(single.rows.size(), 3u);
  EXPECT_EQ(single.rows[0][0], 0.0) << single.rows[0][1];
  EXPECT_EQ(single.rows[1][0], 0.0) << single.rows[1][1];
  ASSERT_EQ(single.rows[2][0], 1.0);
  EXPECT_NEAR(single.rows[2][1], 1.0 + o, 1e-6);
}

// A --param value may be a constant as the equation writes one (session 53; "not a finite
// number" before): a = pi/2 answers as the literal 1.5707963267948966 does, at the closed
// form's t = 5 - pi/2; a value with x, y or z, or one the parser refuses, is named.
TEST_F(QueryTool, ParameterValuesMayBeConstantExpressions) {
  const fs::path rays = write("r.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n-5,0,0,1,0,0,0,inf\n");
  const std::string sphere = "--surface \"x^2+y^2+z^2-a^2\" --clip-sphere 3 ";
  const RunResult expression = run(sphere + "--param \"a = pi/2\" " + common(rays));
  ASSERT_EQ(expression.exitCode, 0) << expression.err;
  const RunResult literal = run(sphere + "--param a=1.5707963267948966 " + common(rays));
  ASSERT_EQ(literal.exitCode, 0) << literal.err;
  ASSERT_EQ(expression.rows.size(), 1u);
  EXPECT_EQ(expression.rows, literal.rows);
  EXPECT_NEAR(expression.rows[0][1], 5 - std::acos(-1.0) / 2, 1e-14);
  const RunResult golden = run(
      "--surface \"x^2+y^2+z^2-a\" --clip-sphere 3 --param \"a=(1+sqrt(5))/2\" " + common(rays));
  ASSERT_EQ(golden.exitCode, 0) << golden.err;
  EXPECT_NEAR(golden.rows[0][1], 5 - std::sqrt((1 + std::sqrt(5.0)) / 2), 1e-14);
  for (const auto& [value, message] :
       {std::pair<std::string, std::string>{"x+1", "a parameter's value may not use x, y or z"},
        {"(1+", "column 4: the equation ends after '+'"},
        {"b*2", "column 1: unknown name 'b'"},
        {"sqrt(-1)", "column 1: sqrt(-1) is not a finite real number"}}) {
    const RunResult r = run(sphere + "--param \"a=" + value + "\" " + common(rays));
    EXPECT_EQ(r.exitCode, 2) << value;
    EXPECT_NE(
        r.err.find("--param a: '" + value + "' is neither a number nor a constant (" + message),
        std::string::npos)
        << r.err;
  }
}

TEST_F(QueryTool, BadInputExitsWithCode2AndLocation) {
  const std::string sphere = "--surface \"x^2+y^2+z^2-1\" --clip-sphere 2 ";
  const fs::path good = write("good.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n");
  struct Case {
    std::string args, expect;
  };
  const std::vector<Case> cases = {
      {sphere +
           common(write("a.csv",
                        "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n0,0,x5,0,0,1,0,inf\n")),
       "a.csv:3: column 'oz'"},
      {sphere + common(write("b.csv", "ox,oy,oz,dx,dy,tnear,tfar\n0,0,-5,0,0,0,inf\n")),
       "b.csv:1: the header has no column 'dz'"},
      {sphere + common(write("c.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0\n")),
       "c.csv:2: expected 8 fields"},
      {sphere + common(write("d.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,nan,0,0,1,0,inf\n")),
       "d.csv:2: column 'oz'"},
      {sphere + common(write("e.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,inf,0,1,0,inf\n")),
       "e.csv:2: column 'dx'"},
      {sphere + common(write("f.csv", "")), "f.csv:1: empty file"},
      {sphere + common(write("oe.csv",
                             "ox,oy,oz,dx,dy,dz,tnear,tfar,org_error\n0,0,-5,0,0,1,0,inf,-1\n")),
       "oe.csv:2: column 'org_error' (field 9): must be >= 0"},
      {sphere + common(write("of.csv",
                             "ox,oy,oz,dx,dy,dz,tnear,tfar,org_error\n0,0,-5,0,0,1,0,inf,inf\n")),
       "of.csv:2: column 'org_error' (field 9): must be finite"},
      // Degenerate rays: zero direction (also by underflow), reversed or negative interval.
      {sphere +
           common(write("g.csv",
                        "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n0,0,-5,0,0,0,0,inf\n")),
       "g.csv:3: column 'dx' (field 4), column 'dy' (field 5), column 'dz' (field 6): the "
       "direction is zero"},
      {sphere + common(write("h.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1e-400,0,inf\n")),
       "h.csv:2: column 'dz' (field 6): '1e-400' underflows to 0"},
      {sphere + common(write("i.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,-1\n")),
       "i.csv:2: column 'tfar' (field 8): must be >= tnear"},
      {sphere + common(write("j.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,3,2\n")),
       "j.csv:2: column 'tfar' (field 8): must be >= tnear"},
      {sphere + common(write("k.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,1e400\n")),
       "k.csv:2: column 'tfar' (field 8): '1e400' overflows"},
      {"--surface \"x^2+y^2+*z\" --clip-sphere 2 " + common(good), "column 9"},
      {"--surface \"x^2+y^2+z^2-a\" --clip-sphere 2 " + common(good),
       "column 13: unknown name 'a' (give it a value with --param a=VALUE)"},
      {"--surface barth " + common(good),
       "column 1: unknown name 'barth' (or did you mean one of the gallery surfaces "
       "'barth-sextic', 'barth-decic'?)"},
      {"--surface torus --param a=1 " + common(good),
       "algray-query: --param a: the gallery surface 'torus' takes no parameters\n"},
      {"--surface \"x²+y²+z²−a\" --clip-sphere 2 " + common(good),
       "column 10: unknown name 'a' (give it a value with --param a=VALUE)\n  x²+y²+z²−a\n"
       "           ^\n"},
      // A tab in the equation is a tab before the caret too (a space left the caret 7
      // columns short of the '(' on a terminal).
      {"--surface \"x^2+\ty^2+(z\" --clip-sphere 2 " + common(good),
       "column 10: unbalanced parenthesis: '(' is never closed\n  x^2+\ty^2+(z\n"
       "      \t    ^\n"},
      // An equation with line breaks: its line, the column in it, and that line under the
      // caret (the caret stood 16 columns into the whole text; session 53).
      {"--surface \"x^2+y^2\n+z²-1 q\" --clip-sphere 2 " + common(good),
       "--surface: line 2, column 7: missing operator before 'q' (write a product with '*')\n"
       "  +z²-1 q\n        ^\n"},
      // An error at the end of a text ending in a line break: at the end of its last line
      // with a character (it was on the empty line after it, the caret under nothing).
      {"--surface \"x^2+\ny^2+ \n\" --clip-sphere 2 " + common(good),
       "line 2, column 5: the equation ends after '+' where an operand is expected\n  y^2+\n"
       "      ^\n"},
      {"--surface \"(x^2+y^2\r\n+z^2-1 = 3\" --clip-sphere 2 " + common(good),
       "line 2, column 8: expected ')' to close '(' at line 1, column 1 but found '='\n"
       "  +z^2-1 = 3\n         ^\n"},
      {"--surface \"x^2-a\" --param a --clip-sphere 2 " + common(good), "--param"},
      {"--surface \"x^2-a\" --param a=zz --clip-sphere 2 " + common(good), "--param"},
      {"--surface \"x^2+y^2+z^2-1\" --param x=1 --clip-sphere 2 " + common(good),
       "algray-query: --param x: clashes with the built-in name 'x'\n"},
      {"--surface \"x^2+y^2+z^2-1\" --param sin=1 --clip-sphere 2 " + common(good),
       "--param sin: clashes"},
      {"--surface \"x^2+y^2+z^2-a\" --param a=1 --param b=2 --clip-sphere 2 " + common(good),
       "algray-query: --param b: is not used by the equation"},
      {"--surface \"x^2+y^2+z^2-a\" --param a=1 --param a=4 --clip-sphere 2 " + common(good),
       "--param a: given more than once"},
      {"--surface \"x^2+y^2+z^2-a\" --param a=1 --param b=2 --param a=1 --clip-sphere 2 " +
           common(good),
       "--param a: given more than once"},
      {"--surface \"x^2+y^2+z^2-1\" " + common(good), "--clip-sphere"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere -1 " + common(good), "--clip-sphere"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box 1,2,3 " + common(good), "--clip-box"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box 1,1,1,0,2,2 " + common(good), "--clip-box"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box -2,-2,-2,2,2,2, " + common(good),
       "algray-query: --clip-box: a value is missing after the last ','\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere 1 --clip-box -1,-1,-1,1,1,1 " + common(good),
       "clip"},
      {sphere + common(good) + " --threads 0", "--threads"},
      {sphere + common(good) + " --threads 0x2", "--threads: '0x2' is not a decimal integer"},
      {sphere + common(good) + " --bogus", "bogus"},
      {sphere + "--rays /nonexistent/rays.csv --out " + (dir / "out.csv").string(), "cannot open"},
      {"--surface \"7\" --clip-sphere 2 " + common(good), "constant"},
      {sphere + "--rays " + good.string() + " --out /nonexistent/out.csv", "--out: cannot write"},
      {sphere + "--rays " + good.string() + " --out ''",
       "algray-query: --out: the file name is empty\n"},
      {sphere + "--rays " + good.string() + " --out " + good.string() + "/x.csv",
       "' is not a directory)\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere 1e30 " + common(good), "scale the scene down"},
      // A directory as IN.csv (was "empty file"), a parameter or radius the user cannot
      // have meant (1e-400 was silently 0, inf reached the library), and the library's own
      // refusals with the options they concern.
      {sphere + "--rays " + dir.string() + " --out " + (dir / "out.csv").string(),
       "algray-query: --rays: '" + dir.string() + "' is a directory\n"},
      {"--surface \"x^2+y^2+z^2-a\" --param a=1e-400 --clip-sphere 2 " + common(good),
       "algray-query: --param a: '1e-400' underflows to 0 in double\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere inf " + common(good),
       "algray-query: --clip-sphere: the radius must be finite and > 0\n"},
      {"--surface \"x-x\" --clip-box -1,-1,-1,1,1,1 " + common(good),
       "algray-query: --surface, --clip-box: "},
      {"--surface \"7\" --clip-sphere 2 " + common(good),
       "algray-query: --surface, --clip-sphere: "},
      // Session 12's sweep: a direction whose t at the clip region overflows double (the
      // hit was reported as a miss), and a read error (reported as an empty file).
      {sphere +
           common(write(
               "sd.csv",
               "ox,oy,oz,dx,dy,dz,tnear,tfar\n-3,0,0,1e-300,0,0,0,inf\n-3,0,0,1e-310,0,0,0,inf\n")),
       "algray-query: --rays: ray 2: the direction is so short that t at the clip region would "
       "overflow double"},
      {sphere + "--rays /proc/self/mem --out " + (dir / "out.csv").string(),
       "algray-query: /proc/self/mem:1: read error"},
      // From the clip centre only the radius over |d| is left of t at the clip region:
      // 2 / 1e-310 overflows as well (o - c = 0 adds no NaN to be caught).
      {sphere + common(write("sc.csv", "ox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,0,1e-310,0,0,0,inf\n")),
       "algray-query: --rays: ray 1: the direction is so short that t at the clip region would "
       "overflow double"},
      // Every axis of a box is checked, and a radius of 0 is no sphere; an infinite box
      // value or parameter is named as not finite, before the library sees it.
      {"--surface \"x^2+y^2+z^2-1\" --clip-box -2,2,-2,2,-2,2 " + common(good),
       "algray-query: --clip-box: need X0 < X1, Y0 < Y1, Z0 < Z1\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box -2,-2,2,2,2,-2 " + common(good),
       "algray-query: --clip-box: need X0 < X1, Y0 < Y1, Z0 < Z1\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box -2,-2,1,2,2,1 " + common(good),
       "algray-query: --clip-box: need X0 < X1, Y0 < Y1, Z0 < Z1\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-sphere 0 " + common(good),
       "algray-query: --clip-sphere: the radius must be finite and > 0\n"},
      {"--surface \"x^2+y^2+z^2-1\" --clip-box -2,-2,-2,2,2,inf " + common(good),
       "algray-query: --clip-box value 6: not a finite number: 'inf'\n"},
      {"--surface \"x^2+y^2+z^2-a\" --param a=inf --clip-sphere 2 " + common(good),
       "algray-query: --param a: not a finite number: 'inf'\n"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << "\nstderr: " << r.err;
  }
  // And the good file works, also behind a UTF-8 byte order mark (Excel's CSV UTF-8).
  EXPECT_EQ(run(sphere + common(good)).exitCode, 0);
  const RunResult bom =
      run(sphere + common(write("bom.csv",
                                "\xef\xbb\xbfox,oy,oz,dx,dy,dz,tnear,tfar\n0,0,-5,0,0,1,0,inf\n")));
  EXPECT_EQ(bom.exitCode, 0) << bom.err;
  ASSERT_EQ(bom.rows.size(), 1u);
  EXPECT_EQ(bom.rows[0][1], 4.0);  // the unit sphere from z = -5 along +z
  // Spaces around a parameter's name and value are quoting ("a= 1" was taken, "a=1 " not).
  for (const char* param : {"\"a= 4\"", "\"a=4 \"", "\" a =4\""}) {
    const RunResult r = run("--surface \"x^2+y^2+z^2-a\" --clip-sphere 3 --param " +
                            std::string(param) + " " + common(good));
    EXPECT_EQ(r.exitCode, 0) << param << "\n" << r.err;
    ASSERT_EQ(r.rows.size(), 1u) << param;
    EXPECT_EQ(r.rows[0][1], 3.0) << param;  // the sphere of radius 2
  }
}

}  // namespace
