/* A small FMI 2.0 co-simulation importer of our own, in plain C, built for
 * Linux and (cross-compiled with MinGW-w64) for Windows: it loads an FMU's
 * binary, points it at fe_server, holds one input and steps, printing the
 * outputs of every step with all their digits. The win64 test runs the
 * Windows build under Wine on the FMU's DLL and the Linux build on its .so,
 * against the same kind of server, and compares the lines.
 *
 * usage: fmi2_driver LIBRARY RESOURCE_URI GUID HOST PORT STEPS DT IN_VR IN_VALUE OUT_VR[,OUT_VR...]
 * exit: 0 ran every step; 1 a call failed (the FMU's messages say why); 2 usage. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2/fmi2.h"

#ifdef _WIN32
#include <windows.h>
static void *open_library(const char *path) { return (void *)LoadLibraryA(path); }
static void *symbol(void *lib, const char *name) { return (void *)GetProcAddress((HMODULE)lib, name); }
static const char *library_error(void) { return "LoadLibrary failed"; }
#else
#include <dlfcn.h>
static void *open_library(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *symbol(void *lib, const char *name) { return dlsym(lib, name); }
static const char *library_error(void) { return dlerror(); }
#endif

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String format, ...) {
  (void)env;
  va_list ap;
  va_start(ap, format);
  fprintf(stderr, "[%s] %s (status %d): ", name ? name : "?", category ? category : "", (int)status);
  vfprintf(stderr, format, ap);
  fputc('\n', stderr);
  va_end(ap);
}

#define LOOKUP(name)                                                     \
  name##TYPE *name = (name##TYPE *)symbol(lib, #name);                   \
  if (!name) {                                                           \
    fprintf(stderr, "fmi2_driver: %s is not exported by %s\n", #name, argv[1]); \
    return 1;                                                            \
  }

#define CHECK(call)                                                      \
  if ((call) != fmi2OK) {                                                \
    fprintf(stderr, "fmi2_driver: %s failed\n", #call);                  \
    return 1;                                                            \
  }

int main(int argc, char **argv) {
  if (argc != 11) {
    fprintf(stderr,
            "usage: fmi2_driver LIBRARY RESOURCE_URI GUID HOST PORT STEPS DT IN_VR IN_VALUE OUT_VR[,OUT_VR...]\n");
    return 2;
  }
  void *lib = open_library(argv[1]);
  if (!lib) {
    fprintf(stderr, "fmi2_driver: cannot load %s: %s\n", argv[1], library_error());
    return 1;
  }
  LOOKUP(fmi2Instantiate) LOOKUP(fmi2SetString) LOOKUP(fmi2SetInteger) LOOKUP(fmi2SetReal) LOOKUP(fmi2GetReal)
  LOOKUP(fmi2SetupExperiment) LOOKUP(fmi2EnterInitializationMode) LOOKUP(fmi2ExitInitializationMode)
  LOOKUP(fmi2DoStep) LOOKUP(fmi2Terminate) LOOKUP(fmi2FreeInstance)
  const long steps = strtol(argv[6], NULL, 10);
  const double dt = strtod(argv[7], NULL), in_value = strtod(argv[9], NULL);
  const fmi2ValueReference in_vr = (fmi2ValueReference)strtoul(argv[8], NULL, 10);
  fmi2ValueReference out_vr[16];
  size_t n_out = 0;
  for (char *p = strtok(argv[10], ","); p && n_out < 16; p = strtok(NULL, ",")) out_vr[n_out++] = (fmi2ValueReference)strtoul(p, NULL, 10);
  const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
  fmi2Component c = fmi2Instantiate("driver", fmi2CoSimulation, argv[3], argv[2], &callbacks, fmi2False, fmi2False);
  if (!c) {
    fprintf(stderr, "fmi2_driver: fmi2Instantiate failed\n");
    return 1;
  }
  const fmi2ValueReference vr_host = 1000000, vr_port = 1000001;
  const fmi2String host = argv[4];
  const fmi2Integer port = (fmi2Integer)strtol(argv[5], NULL, 10);
  CHECK(fmi2SetString(c, &vr_host, 1, &host))
  CHECK(fmi2SetInteger(c, &vr_port, 1, &port))
  CHECK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, (double)steps * dt))
  CHECK(fmi2EnterInitializationMode(c))
  CHECK(fmi2ExitInitializationMode(c))
  for (long k = 0; k < steps; ++k) {
    CHECK(fmi2SetReal(c, &in_vr, 1, &in_value))
    CHECK(fmi2DoStep(c, (double)k * dt, dt, fmi2True))
    double y[16];
    CHECK(fmi2GetReal(c, out_vr, n_out, y))
    printf("%ld", k + 1);
    for (size_t i = 0; i < n_out; ++i) printf(" %.17g", y[i]);
    printf("\n");
  }
  CHECK(fmi2Terminate(c))
  fmi2FreeInstance(c);
  return 0;
}
