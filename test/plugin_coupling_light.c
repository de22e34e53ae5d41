/* The light-body case of plugin_coupling (see that file): a 0.5 kg box
 * resting on a cloth pinned at its corners. Listed as Disabled in
 * CMakeLists.txt: it settles and its pin forces balance, but changes of the
 * contact set under it kick it past the 1 mm/s bound now and then (issue 4). */
#define COUPLING_LIGHT 1
#include "plugin_coupling.c"
