# examples/silos.mk - silo discharge and filling against Beverloo and Janssen (included by Makefile.am).
