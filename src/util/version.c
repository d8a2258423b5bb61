/* The version of the library loaded (include/railride/version.h). */
#include "railride/version.h"

const char *rr_version(void) { return RR_VERSION_STRING; }
