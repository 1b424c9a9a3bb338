/*
 * consumer.cpp - a C++17 host built by .ci/run outside the source tree
 * against the INSTALLED library with `pkg-config --cflags --libs granmpm`
 * and -Wall -Wextra -Wpedantic -Werror: the header must be usable from a
 * C++ code that builds with -Werror, and the library from C++ (RAII
 * ownership of the domain, zero-copy views into std containers).
 *
 * Scene: an elastic block falls freely in plane strain far from every
 * face for 10 steps of 1 ms; every point's vertical velocity must be g t.
 * Exit status 0 when every check holds.
 */
#include <granmpm.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace {

struct domain_deleter {
  void operator()(gm_domain *domain) const {
    gm_domain_destroy(domain);
  }
};
using domain_ptr = std::unique_ptr<gm_domain, domain_deleter>;

int failures = 0;

void check(bool condition, const char *what) {
  if (!condition) {
    std::fprintf(stderr, "consumer.cpp: FAILED: %s\n", what);
    failures++;
  }
}

bool ok(gm_status status, const gm_domain *domain, const char *call) {
  if (status == GM_OK)
    return true;
  std::fprintf(stderr, "consumer.cpp: FAILED: %s: %s (%s)\n", call,
               gm_strerror(status),
               domain ? gm_domain_last_error(domain) : gm_last_create_error());
  failures++;
  return false;
}

} // namespace

int main() {
  constexpr double gravity_y = -9.75; // m/s^2, exact in binary
  constexpr double dt = 1e-3;         // s, below the stable ~1.7e-3 s
  constexpr int steps = 10;

  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = def.extent[1] = 1.0; // m
  def.cell_size = 0.125;               // m
  def.gravity[1] = gravity_y;
  gm_domain *raw = nullptr;
  if (!ok(gm_domain_create(&def, &raw), nullptr, "gm_domain_create"))
    return 1;
  domain_ptr domain(raw);

  gm_elastic_def elastic = gm_elastic_def_default();
  int material = -1;
  if (!ok(gm_domain_add_elastic(domain.get(), &elastic, &material),
          domain.get(), "gm_domain_add_elastic"))
    return 1;
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = fill.lower[1] = 0.25; // m
  fill.upper[0] = fill.upper[1] = 0.75; // m
  size_t count = 0;
  if (!ok(gm_domain_fill_box(domain.get(), &fill, nullptr, &count),
          domain.get(), "gm_domain_fill_box"))
    return 1;
  check(count == 64, "64 points (8 x 8)");

  for (int step = 0; step < steps; step++)
    if (!ok(gm_domain_step(domain.get(), dt), domain.get(), "gm_domain_step"))
      return 1;

  // Zero-copy view of the vertical velocity. Far from every face only
  // gravity acts and a stress-free falling block has no internal force, so
  // v_y = g t for every point; 1e-12 relative allows the rounding of ten
  // FLIP updates.
  const double *view = nullptr;
  if (!ok(gm_domain_view_field(domain.get(), GM_FIELD_VELOCITY, 1, &view),
          domain.get(), "gm_domain_view_field"))
    return 1;
  std::vector<double> velocity_y(view,
                                 view + gm_domain_point_count(domain.get()));
  const double expected = gravity_y * dt * steps;
  double worst = 0.0;
  for (double v : velocity_y)
    worst = std::fmax(worst, std::fabs(v - expected));
  check(worst <= 1e-12 * std::fabs(expected), "v_y = g t for every point");

  if (failures) {
    std::fprintf(stderr, "consumer.cpp: %d check(s) failed\n", failures);
    return 1;
  }
  std::printf("consumer.cpp: libgranmpm %s from C++%ld: v_y = %.17g m/s, "
              "largest deviation %.2e: all checks passed\n",
              gm_version(), static_cast<long>(__cplusplus / 100 % 100),
              expected, worst);
  return 0;
}
