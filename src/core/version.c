/* The library's version (hairkit/core.h, hairkit/version.h). */
#include "hairkit/core.h"

const char *hk_version(void) { return HK_VERSION_STRING; }
