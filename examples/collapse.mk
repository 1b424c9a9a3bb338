# examples/collapse.mk - column collapse, the demo and the speed-vs-accuracy chart (included by Makefile.am).

# Planar granular column collapse against Lube et al. (2005).
noinst_PROGRAMS += examples/column_collapse
examples_column_collapse_SOURCES = examples/column_collapse.c \
	examples/collapse_laws.h examples/collapse_material.h $(EXAMPLE_COMMON)
examples_column_collapse_LDADD = lib/libgranmpm.la -lm
examples_column_collapse_CPPFLAGS = -I$(top_srcdir)/include -I$(top_srcdir)/examples

# 3D column collapse (quarter cylinder or square column) against Lube et
# al. (2004) and the axisymmetric run of the same column.
noinst_PROGRAMS += examples/column_collapse_3d
examples_column_collapse_3d_SOURCES = examples/column_collapse_3d.c \
	examples/collapse_laws.h examples/collapse_material.h $(EXAMPLE_COMMON)
examples_column_collapse_3d_LDADD = lib/libgranmpm.la -lm
examples_column_collapse_3d_CPPFLAGS = -I$(top_srcdir)/include -I$(top_srcdir)/examples
# Its run-out against the axisymmetric run of the same column, within 5 %
# at R0/6 and R0/8 (issue 16 item 3; larger cells: validate/collapse_3d.sh).
TESTS += tests/scripts/collapse_3d_axisym.sh
EXTRA_DIST += tests/scripts/collapse_3d_axisym.sh

# Validation against Lube et al. (2005): two aspect ratios, +-15 %.
check_PROGRAMS += tests/physics/test_column_collapse
tests_physics_test_column_collapse_SOURCES = tests/physics/test_column_collapse.c
tests_physics_test_column_collapse_CFLAGS = $(TEST_CFLAGS) -I$(top_srcdir)/examples
tests_physics_test_column_collapse_LDADD = $(TEST_LDADD)

# The setting of docs/convergence.md sec. 20 under refinement (issue 13 item
# 4): the scene of the convergence probes, bench/convergence/collapse_scene.c.
check_PROGRAMS += tests/physics/test_collapse_refinement
tests_physics_test_collapse_refinement_SOURCES = \
	tests/physics/test_collapse_refinement.c bench/convergence/collapse_scene.c \
	bench/convergence/collapse_scene.h
tests_physics_test_collapse_refinement_CFLAGS = $(TEST_CFLAGS) \
	-I$(top_srcdir)/bench/convergence -I$(top_srcdir)/include \
	-I$(top_srcdir)/examples
tests_physics_test_collapse_refinement_LDADD = $(TEST_LDADD)

# The demo: a tall column (a = 3, L0 = 10 cm, 5 mm cells, 4800 points,
# Granular uGIMP; about 20 s on one core), progress on stderr, VTU + CSV +
# PNG snapshots in $(DEMO_OUT)/column_collapse, run-out against the law as
# the last line.
demo-collapse: examples/column_collapse
	$(MKDIR_P) $(DEMO_OUT)/column_collapse
	./examples/column_collapse --aspect 3 --length 0.1 --cell 0.005 \
	  --out $(DEMO_OUT)/column_collapse

# The speed-vs-accuracy charts in the source tree: column collapse,
# bench/results/accuracy_vs_cost.{csv,png} (92 runs), and the moderate flow
# down a slope, accuracy_vs_cost_slope.{csv,png} (24 runs); CHART_JOBS runs
# at a time (cost: docs/performance.md, "The speed-vs-accuracy charts").
CHART_JOBS ?= 2
bench-chart: examples/column_collapse examples/papers/seyedan2021_slope_density
	SCENE=collapse $(SHELL) $(top_srcdir)/bench/chart.sh \
	  ./examples/column_collapse $(top_srcdir)/bench/results $(CHART_JOBS)
	SCENE=slope $(SHELL) $(top_srcdir)/bench/chart.sh \
	  ./examples/papers/seyedan2021_slope_density $(top_srcdir)/bench/results $(CHART_JOBS)

EXTRA_DIST += bench/chart.sh examples/README.md bench/convergence
.PHONY: demo-collapse bench-chart
