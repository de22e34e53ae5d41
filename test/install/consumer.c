/* Uses the installed core: its version must be the header's, and the default
 * descriptor must be a valid grid. Exits 0 on success. */
#include <stdio.h>
#include <string.h>

#include <odecloth/cloth.h>

int main(void)
{
    char expected[32];
    snprintf(expected, sizeof expected, "%d.%d.%d", ODECLOTH_VERSION_MAJOR,
             ODECLOTH_VERSION_MINOR, ODECLOTH_VERSION_PATCH);
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
    printf("odecloth %s, default grid %d x %d\n", v, d.rows, d.cols);
    return 0;
}
