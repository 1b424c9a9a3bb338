# libgranmpm - thin wrapper: bootstraps an out-of-tree autotools build in
# $(BUILD) and forwards the usual targets to it. The real build is
# Makefile.am; see README.md.
#
#   make demo            build everything, run the demo (writes out/)
#   make bench-chart     speed vs accuracy chart (bench/results/)
#   make check           build and run the whole test suite
#   make bench           build and run the benchmark (CSV on stdout)
#   make bench-yardstick the library against ../shared/yardstick, interleaved
#                        (YARDSTICK_ARGS=--full; bench/README.md), after
#                        bench-triad
#   make bench-triad     the machine's triad bandwidth (bench/results/)
#   make bench-alternate builds of the library stepped in turn in one process
#                        (ALTERNATE_ARGS; bench/README.md)
#   make install PREFIX=/usr/local DESTDIR=
#   make abi-check       compare the library ABI with abi/libgranmpm.abi
#   make distcheck       build, test and check the release tarball
#   make validate        the refinement studies (validate/, ~1.5 h on 2 cores)
#   make fuzz            build the libFuzzer harnesses (clang) and run each
#                        for FUZZ_TIME seconds (default 600; fuzz/README.md)
BUILD ?= build
PREFIX ?= /usr/local
DESTDIR ?=
CONFIGURE_FLAGS ?=
TOP := $(CURDIR)

FORWARD := all check demo demo-bar demo-collapse bench bench-chart \
	bench-yardstick bench-triad bench-alternate install \
	uninstall abi-check abi-dump check-valgrind installcheck
# Forwarded without prefix/DESTDIR: a command-line prefix would reach
# distcheck's own install step through MAKEFLAGS and override its private
# temporary prefix (installing into the real PREFIX instead).
DIST_FORWARD := dist distcheck

# 'configure' is a real file, so it is not .PHONY: a phony prerequisite
# would rerun autoreconf and configure on every make.
.PHONY: $(FORWARD) $(DIST_FORWARD) clean distclean format format-check fuzz \
	validate

all:

$(FORWARD): $(BUILD)/Makefile
	$(MAKE) -C $(BUILD) $@ prefix=$(PREFIX) DESTDIR=$(DESTDIR) \
	  DEMO_OUT=$(TOP)/out

$(DIST_FORWARD): $(BUILD)/Makefile
	$(MAKE) -C $(BUILD) $@

configure: configure.ac Makefile.am
	autoreconf -fi

$(BUILD)/Makefile: configure
	mkdir -p $(BUILD)
	cd $(BUILD) && $(TOP)/configure --prefix=$(PREFIX) $(CONFIGURE_FLAGS)

clean:
	-$(MAKE) -C $(BUILD) clean

distclean:
	rm -rf $(BUILD) $(FUZZ_BUILD) out

# The refinement studies (issue 13 item 4): results into validate/results,
# plots into docs/.
validate: all
	sh validate/collapse.sh
	sh validate/collapse_size.sh
	sh validate/collapse_3d.sh
	sh validate/silo_refinement.sh
	sh validate/silo_edge.sh
	sh validate/silo_similar.sh

# Fuzzing: a private static build with clang, libFuzzer, ASan and UBSan.
FUZZ_BUILD ?= build-fuzz
FUZZ_TIME ?= 600
FUZZ_CC ?= clang
FUZZ_SANITIZE = -fsanitize=address,undefined -fno-sanitize-recover=all
fuzz: $(FUZZ_BUILD)/Makefile
	$(MAKE) -C $(FUZZ_BUILD) fuzz/fuzz_api fuzz/fuzz_checkpoint
	sh fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_TIME)

$(FUZZ_BUILD)/Makefile: configure
	mkdir -p $(FUZZ_BUILD)
	cd $(FUZZ_BUILD) && $(TOP)/configure --quiet --enable-fuzz \
	  --disable-shared FC=no CC=$(FUZZ_CC) \
	  CFLAGS="-g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer-no-link $(FUZZ_SANITIZE)" \
	  LDFLAGS="$(FUZZ_SANITIZE)"

CLANG_FORMAT ?= clang-format
FORMAT_FILES = $(wildcard include/*.h include/granmpm/*.h lib/*/*.c lib/*/*.h \
	tests/*/*.c tests/*/*.h examples/*.c examples/*/*.c bench/*.c .ci/*.c .ci/*.cpp \
	fuzz/*.c fuzz/*.h)
format:
	$(CLANG_FORMAT) -i $(FORMAT_FILES)
format-check:
	$(CLANG_FORMAT) --dry-run --Werror $(FORMAT_FILES)
