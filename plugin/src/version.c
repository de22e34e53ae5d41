/* The plugin's version is the core's: they are built and released together. */
#include "odecloth/cloth.h"
#include "odecloth/dcloth.h"

const char *dClothGetVersion(void) { return cloth_version(); }
