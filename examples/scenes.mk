# examples/scenes.mk - the scenes of 000, 001 and 002 (included by Makefile.am).
