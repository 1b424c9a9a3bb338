# examples/silos.mk - silo discharge and filling against Beverloo and Janssen (included by Makefile.am).
noinst_PROGRAMS += examples/papers/wieckowski1999_silo_discharge examples/papers/wieckowski2004_silo_filling_janssen
examples_papers_wieckowski1999_silo_discharge_SOURCES = examples/papers/wieckowski1999_silo_discharge.c \
	examples/papers/silo_discharge_3d.c examples/papers/silo_discharge_3d.h \
	examples/papers/silo_slice_3d.c examples/papers/silo_slice_3d.h $(EXAMPLE_COMMON)
examples_papers_wieckowski1999_silo_discharge_LDADD = lib/libgranmpm.la -lm
examples_papers_wieckowski1999_silo_discharge_CPPFLAGS = -I$(top_srcdir)/include -I$(top_srcdir)/examples
# The 3D silo (a quarter square silo, circular orifice) against the
# axisymmetric silo of the same D, B, H and cell, within 5 % at D/6
# (issue 16 item 3; docs/3d.md).
TESTS += tests/scripts/silo_3d_axisym.sh
EXTRA_DIST += tests/scripts/silo_3d_axisym.sh tests/scripts/slow_case.sh
# Beverloo's exponent for the circular orifice, axisymmetric silo: 2.5 +-
# 0.15 with the cell as grain size over D = 6 to 16 cells (docs/3d.md).
TESTS += tests/scripts/silo_beverloo_axisym.sh
EXTRA_DIST += tests/scripts/silo_beverloo_axisym.sh tests/scripts/beverloo_fit.awk
# The README's recommended silo setting (B-splines, Perzyna, the orifice's
# edge node open): the circular orifice's rate within 5 % from D/12 to
# D/24, Beverloo's exponent 2.5 +- 0.15 with k d fitted (section 38).
TESTS += tests/scripts/silo_recommended.sh
EXTRA_DIST += tests/scripts/silo_recommended.sh
# The orifice's two floor edges (--edge-node held / open) bracket one
# rate and the bracket closes as the cell (docs/convergence.md section 38).
TESTS += tests/scripts/silo_edge_bracket.sh
EXTRA_DIST += tests/scripts/silo_edge_bracket.sh
# The B-spline rigid floor under USL, MUSL and USF: each runs, and the
# rates agree within 5 % (docs/convergence.md section 35).
TESTS += tests/scripts/silo_bspline_rigid_floor.sh
EXTRA_DIST += tests/scripts/silo_bspline_rigid_floor.sh
examples_papers_wieckowski2004_silo_filling_janssen_SOURCES = examples/papers/wieckowski2004_silo_filling_janssen.c $(EXAMPLE_COMMON)
examples_papers_wieckowski2004_silo_filling_janssen_LDADD = lib/libgranmpm.la -lm
examples_papers_wieckowski2004_silo_filling_janssen_CPPFLAGS = -I$(top_srcdir)/include -I$(top_srcdir)/examples

check_PROGRAMS += tests/physics/test_beverloo
tests_physics_test_beverloo_SOURCES = tests/physics/test_beverloo.c
tests_physics_test_beverloo_CFLAGS = $(TEST_CFLAGS)
tests_physics_test_beverloo_LDADD = $(TEST_LDADD)

# A silo filled by pouring (Wieckowski's filling model), at rest, against
# Janssen: the scene of examples/papers/wieckowski2004_silo_filling_janssen at a third of its size.
check_PROGRAMS += tests/physics/test_silo_filling
tests_physics_test_silo_filling_SOURCES = tests/physics/test_silo_filling.c
tests_physics_test_silo_filling_CFLAGS = $(TEST_CFLAGS)
tests_physics_test_silo_filling_LDADD = $(TEST_LDADD)
