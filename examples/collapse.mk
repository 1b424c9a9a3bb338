# examples/collapse.mk - column collapse, the demo and the speed-vs-accuracy chart (included by Makefile.am).
