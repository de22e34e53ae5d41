/* Uses the installed plugin together with ODE itself. Exits 0 on success. */
#include <stdio.h>
#include <string.h>

#include <odecloth/cloth.h>
#include <odecloth/dcloth.h>

int main(void)
{
    dInitODE2(0);
    dWorldID world = dWorldCreate();
    dWorldDestroy(world);
    dCloseODE();

    const char *v = dClothGetVersion();
    if (v == NULL || strcmp(v, cloth_version()) != 0) {
        fprintf(stderr, "dClothGetVersion() = %s, cloth_version() = %s\n", v ? v : "(null)", cloth_version());
        return 1;
    }
    printf("odecloth ODE plugin %s\n", v);
    return 0;
}
