/* Filling a psim_error (include/psim/psim.h): the one helper every layer
 * of the library reports its errors through.  Not installed or exported
 * from libpsim.so. */
#ifndef PSIM_BASE_ERROR_H
#define PSIM_BASE_ERROR_H

#include "psim/psim.h"

/* Format the message into err->msg (truncated to fit); err NULL: nothing. */
void psim_error_set(psim_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
