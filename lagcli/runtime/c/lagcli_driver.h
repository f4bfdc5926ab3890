/* The command-line driver of a generated lagcli model (lagcli_driver.c): shipped with
 * lagcli (lagcli/runtime/c/) and copied next to every generated C model. The generated
 * <name>_main.c is `return lagcli_driver_main(&<name>_model, argc, argv);`. */
#ifndef LAGCLI_DRIVER_H
#define LAGCLI_DRIVER_H

#include "lagcli_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parse the options (usage: --help), integrate from t = 0 and print the CSV of
 * `lagcli simulate` on stdout. Returns the exit status: 0, 1 (run-time failure, the
 * rows so far printed) or 2 (bad options). */
int lagcli_driver_main(const lagcli_model *model, int argc, char **argv);

#ifdef __cplusplus
}
#endif

#endif /* LAGCLI_DRIVER_H */
