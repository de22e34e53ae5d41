/* Links the plugin alone (no -lodecloth) with an rpath to the installed
 * libdir and runs without LD_LIBRARY_PATH: the plugin must find the core
 * library by its own RUNPATH. */
#include <stdio.h>

#include "odecloth/dcloth.h"

int main(void)
{
    dInitODE();
    dWorldID w = dWorldCreate();
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    int rc = dClothCreate(w, 0, &d, &c, &err) == CLOTH_OK && dClothStep(c, 1.0 / 60.0) == CLOTH_OK ? 0 : 1;
    if (rc) fprintf(stderr, "consumer_plugin_only: %s\n", c ? dClothGetLastError(c) : err.message);
    dClothDestroy(c);
    dWorldDestroy(w);
    dCloseODE();
    if (!rc) printf("consumer_plugin_only: ok\n");
    return rc;
}
