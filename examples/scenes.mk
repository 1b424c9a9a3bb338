# examples/scenes.mk - the scenes of 000, 001 and 002 (included by Makefile.am).
# The five examples of 000 sec 4 and Kumar's impact slope (004 sec 3.3.5),
# and the stability test of issue 6.
SCENE_CPPFLAGS = -I$(top_srcdir)/include -I$(top_srcdir)/examples
SCENE_LDADD = lib/libgranmpm.la -lm

noinst_PROGRAMS += examples/papers/seyedan2021_disconnected_1d examples/papers/seyedan2021_slope_density \
	examples/papers/seyedan2021_avalanche examples/papers/seyedan2021_silo_filling examples/papers/seyedan2021_impact_force \
	examples/papers/kumar2015_impact_slope
examples_papers_seyedan2021_disconnected_1d_SOURCES = examples/papers/seyedan2021_disconnected_1d.c $(EXAMPLE_COMMON)
examples_papers_seyedan2021_disconnected_1d_LDADD = $(SCENE_LDADD)
examples_papers_seyedan2021_disconnected_1d_CPPFLAGS = $(SCENE_CPPFLAGS)
examples_papers_seyedan2021_slope_density_SOURCES = examples/papers/seyedan2021_slope_density.c $(EXAMPLE_COMMON)
examples_papers_seyedan2021_slope_density_LDADD = $(SCENE_LDADD)
examples_papers_seyedan2021_slope_density_CPPFLAGS = $(SCENE_CPPFLAGS)
examples_papers_seyedan2021_avalanche_SOURCES = examples/papers/seyedan2021_avalanche.c $(EXAMPLE_COMMON)
examples_papers_seyedan2021_avalanche_LDADD = $(SCENE_LDADD)
examples_papers_seyedan2021_avalanche_CPPFLAGS = $(SCENE_CPPFLAGS)
examples_papers_seyedan2021_silo_filling_SOURCES = examples/papers/seyedan2021_silo_filling.c $(EXAMPLE_COMMON)
examples_papers_seyedan2021_silo_filling_LDADD = $(SCENE_LDADD)
examples_papers_seyedan2021_silo_filling_CPPFLAGS = $(SCENE_CPPFLAGS)
examples_papers_seyedan2021_impact_force_SOURCES = examples/papers/seyedan2021_impact_force.c $(EXAMPLE_COMMON)
examples_papers_seyedan2021_impact_force_LDADD = $(SCENE_LDADD)
examples_papers_seyedan2021_impact_force_CPPFLAGS = $(SCENE_CPPFLAGS)
examples_papers_kumar2015_impact_slope_SOURCES = examples/papers/kumar2015_impact_slope.c $(EXAMPLE_COMMON)
examples_papers_kumar2015_impact_slope_LDADD = $(SCENE_LDADD)
examples_papers_kumar2015_impact_slope_CPPFLAGS = $(SCENE_CPPFLAGS)

check_PROGRAMS += tests/physics/test_stability
tests_physics_test_stability_SOURCES = tests/physics/test_stability.c
tests_physics_test_stability_CFLAGS = $(TEST_CFLAGS)
tests_physics_test_stability_LDADD = $(TEST_LDADD)
