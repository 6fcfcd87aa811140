/* A plain C FMI 2.0 Co-Simulation host for the native bearing FMU: no Python anywhere.
 *
 *   cc -O2 example_host.c -I <fmpy>/c-code -o example_host -ldl
 *   ./example_host BINARY.so GUID y z vy vz omega [N_STEPS]
 *   python -m ziglang cc -target x86_64-windows-gnu -O2 example_host.c -I <fmpy>/c-code -o example_host.exe
 *   wine64 example_host.exe BINARY.dll GUID y z vy vz omega          (or on Windows)
 *
 * Loads the binary (binaries/<platform>/<modelIdentifier>.so, .dll or .dylib of the extracted FMU), instantiates it with
 * logging on (messages to stdout), initialises it, sets the inputs and takes one doStep of
 * 1e-4 s; prints "status <s>" and the outputs Fy Fz Kyy Kyz Kzy Kzz Cyy Cyz Czy Czz
 * eccentricity (%.17g). With N_STEPS > 0 it then times N_STEPS doSteps at states moving
 * around the given one ("doStep_us") and N_STEPS conformant iterations (restore the state
 * saved at the step's start, set the inputs, doStep, get the outputs: "iteration_us"), as a
 * master iterating within a step does. What a system simulator does with any FMU. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fmi2Functions.h"

#ifdef _WIN32
#include <windows.h>
typedef HMODULE Library;
static Library open_library(const char *path) { return LoadLibraryA(path); }
static const char *open_error(void) { return "LoadLibrary failed"; }
static void *symbol(Library lib, const char *name) { return (void *)GetProcAddress(lib, name); }
static void close_library(Library lib) { FreeLibrary(lib); }
#else
#include <dlfcn.h>
typedef void *Library;
static Library open_library(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static const char *open_error(void) { return dlerror(); }
static void *symbol(Library lib, const char *name) { return dlsym(lib, name); }
static void close_library(Library lib) { dlclose(lib); }
#endif

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    (void)env;
    printf("log [%s] %s: %s\n", category ? category : "", name ? name : "", message ? message : "");
    (void)status;
}

#define LOAD(f) f##TYPE *f = (f##TYPE *)symbol(lib, #f); if (!f) { printf("missing %s\n", #f); return 3; }

static double now(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC); /* C11: glibc and the Universal C Runtime both have it */
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv) {
    if (argc < 8) {
        printf("usage: %s BINARY GUID y z vy vz omega [N_STEPS]\n", argv[0]);
        return 2;
    }
    Library lib = open_library(argv[1]);
    if (!lib) {
        printf("cannot load %s: %s\n", argv[1], open_error());
        return 3;
    }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep) LOAD(fmi2Terminate)
    LOAD(fmi2FreeInstance) LOAD(fmi2GetFMUstate) LOAD(fmi2SetFMUstate) LOAD(fmi2FreeFMUstate)
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("host", fmi2CoSimulation, argv[2], "", &cb, fmi2False, fmi2True);
    if (!c) {
        printf("instantiate failed\n");
        return 4;
    }
    fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    fmi2EnterInitializationMode(c);
    if (fmi2ExitInitializationMode(c) > fmi2Warning) {
        printf("initialisation failed\n");
        return 5;
    }
    const fmi2ValueReference in[5] = {0, 1, 2, 3, 4};
    const fmi2ValueReference out[11] = {5, 6, 9, 10, 11, 12, 13, 14, 15, 16, 7};
    double x[5], o[11];
    for (int i = 0; i < 5; i++) x[i] = atof(argv[3 + i]);
    fmi2SetReal(c, in, 5, x);
    fmi2Status s = fmi2DoStep(c, 0.0, 1e-4, fmi2True);
    fmi2GetReal(c, out, 11, o);
    printf("status %d\n", (int)s);
    printf("outputs");
    for (int i = 0; i < 11; i++) printf(" %.17g", o[i]);
    printf("\n");
    int n = argc > 8 ? atoi(argv[8]) : 0;
    if (n > 0 && s == fmi2OK) {
        double x1[5], t0, sink = 0.0, cr = fmax(hypot(x[0], x[1]), 1e-7);
        int bad = 0;
        /* doStep at states moving on a small circle around the given one */
        t0 = now();
        for (int k = 0; k < n; k++) {
            double a = 1e-3 * k;
            x1[0] = x[0] + 1e-3 * cr * cos(a);
            x1[1] = x[1] + 1e-3 * cr * sin(a);
            x1[2] = x[2];
            x1[3] = x[3];
            x1[4] = x[4];
            fmi2SetReal(c, in, 5, x1);
            bad += fmi2DoStep(c, 1e-4 * (k + 1), 1e-4, fmi2True) != fmi2OK;
            fmi2GetReal(c, out, 11, o);
            sink += o[0];
        }
        double step = (now() - t0) / n;
        /* conformant iteration: state saved once per step, restored at every iteration */
        fmi2FMUstate st = NULL;
        fmi2GetFMUstate(c, &st);
        t0 = now();
        for (int k = 0; k < n; k++) {
            double a = 1e-3 * k;
            x1[0] = x[0] + 1e-3 * cr * cos(a);
            x1[1] = x[1] + 1e-3 * cr * sin(a);
            fmi2SetFMUstate(c, st);
            fmi2SetReal(c, in, 5, x1);
            bad += fmi2DoStep(c, 1e-4 * (n + 1), 1e-4, fmi2False) != fmi2OK; /* from the state's time */
            fmi2GetReal(c, out, 11, o);
            sink += o[0];
        }
        double iter = (now() - t0) / n;
        fmi2FreeFMUstate(c, &st);
        printf("doStep_us %.4f iteration_us %.4f refused %d checksum %.6g\n", 1e6 * step, 1e6 * iter, bad, sink);
    }
    fmi2Terminate(c);
    fmi2FreeInstance(c);
    close_library(lib);
    return 0;
}
