/* Broadphase for continuous collision: a hashed uniform grid of cubic cells (the median box's largest
 * side) over swept boxes, rebuilt per call. Boxes over SWEEP_GRID_MAX_CELLS cells, far out or not
 * finite go to a list every query scans, so a blown-up displacement costs one pass, not a cell loop. */
#ifndef ODECLOTH_SWEEP_GRID_H
#define ODECLOTH_SWEEP_GRID_H

#include "tuning.h"

typedef struct sweep_grid sweep_grid;

sweep_grid *oc_sweep_grid_create(void);    /* NULL: out of memory */
void oc_sweep_grid_destroy(sweep_grid *g); /* NULL is fine */

/* Files n boxes, 6 doubles each (low corner, high corner), kept by pointer
 * until the next build. Returns 0, or -1 out of memory. */
int oc_sweep_grid_build(sweep_grid *g, const double *box, int n);

/* The boxes that overlap box (closed intervals), each once, as indices into
 * *items, valid until the next query or build. Returns their number. */
int oc_sweep_grid_query(sweep_grid *g, const double *box, const int **items);

/* Boxes filed in the big list at the last build (for tests and stats). */
int oc_sweep_grid_big(const sweep_grid *g);

/* The box around every box filed (empty, low above high, when none is):
 * a query box that misses it meets nothing. */
const double *oc_sweep_grid_bound(const sweep_grid *g);

#endif
