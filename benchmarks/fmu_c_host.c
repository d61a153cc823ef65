/* A minimal FMI 3.0 host in C, no Python of its own (benchmarks/run_all.py, bench_fmu):
 * loads the contact element FMU's binary, sets lateral_shift and vertical_position
 * (value references 15, 16) in initialization mode, runs one doStep and prints
 * force_x..torque_z (27..32).  Shows what a non-Python tool needs to run the FMU
 * (docs/multibody.md): libpython preloaded, PYTHONHOME and PYTHONPATH. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include "fmi3Functions.h"
static void logger(fmi3InstanceEnvironment e, fmi3Status s, fmi3String c, fmi3String m) {
    fprintf(stderr, "[%d] %s: %s\n", (int)s, c, m);
}
int main(int argc, char **argv) {
    if (argc < 6) { fprintf(stderr, "usage: host LIB RESOURCES TOKEN Y Z\n"); return 2; }
    void *h = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!h) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 3; }
    fmi3InstantiateCoSimulationTYPE *inst = dlsym(h, "fmi3InstantiateCoSimulation");
    fmi3EnterInitializationModeTYPE *enter = dlsym(h, "fmi3EnterInitializationMode");
    fmi3ExitInitializationModeTYPE *exit_ = dlsym(h, "fmi3ExitInitializationMode");
    fmi3SetFloat64TYPE *setf = dlsym(h, "fmi3SetFloat64");
    fmi3GetFloat64TYPE *getf = dlsym(h, "fmi3GetFloat64");
    fmi3DoStepTYPE *step = dlsym(h, "fmi3DoStep");
    fmi3TerminateTYPE *term = dlsym(h, "fmi3Terminate");
    fmi3FreeInstanceTYPE *freei = dlsym(h, "fmi3FreeInstance");
    fmi3Instance c = inst("host", argv[3], argv[2], fmi3False, fmi3False, fmi3False, fmi3False,
                          NULL, 0, NULL, logger, NULL);
    if (!c) { fprintf(stderr, "instantiate failed\n"); return 4; }
    fmi3ValueReference in[2] = {15, 16}, out[6] = {27, 28, 29, 30, 31, 32};
    fmi3Float64 u[2] = {atof(argv[4]), atof(argv[5])}, y[6];
    if (enter(c, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK) return 5;
    if (setf(c, in, 2, u, 2) != fmi3OK) return 6;
    if (exit_(c) != fmi3OK) return 7;
    fmi3Boolean ev, term_, early; fmi3Float64 last;
    if (step(c, 0.0, 1e-3, fmi3True, &ev, &term_, &early, &last) != fmi3OK) return 8;
    if (getf(c, out, 6, y, 6) != fmi3OK) return 9;
    for (int i = 0; i < 6; i++) printf("%.17g\n", y[i]);
    term(c); freei(c);
    return 0;
}
