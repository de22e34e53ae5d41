/* Uses the installed core: its version must be the header's, the default
 * descriptor must be a valid grid, and the fabric header (installed beside
 * cloth.h) must give it a material. Exits 0 on success. */
#include <stdio.h>
#include <string.h>

#include <odecloth/cloth.h>
#include <odecloth/fabric.h>

int main(void)
{
    char expected[32];
    snprintf(expected, sizeof expected, "%d.%d.%d", ODECLOTH_VERSION_MAJOR, ODECLOTH_VERSION_MINOR,
             ODECLOTH_VERSION_PATCH);
    const char *v = cloth_version();
    if (v == NULL || strcmp(v, expected) != 0) {
        fprintf(stderr, "cloth_version() = %s, header says %s\n", v ? v : "(null)", expected);
        return 1;
    }
    cloth_desc d = cloth_default_desc();
    if (d.rows < 3 || d.cols < 3) {
        fprintf(stderr, "cloth_default_desc(): %d x %d grid\n", d.rows, d.cols);
        return 1;
    }
    cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    cloth_error err;
    if (cloth_fabric_apply(&f, &d, &err) != CLOTH_OK) {
        fprintf(stderr, "cloth_fabric_apply: %s\n", err.message);
        return 1;
    }
    printf("odecloth %s, default grid %d x %d, cotton k_b %g N/m\n", v, d.rows, d.cols, d.material.k_b);
    return 0;
}
