/*
 * odecloth ODE plugin: cloth in an ODE world.
 *
 * The plugin is the glue between the pure C cloth core (odecloth/cloth.h) and
 * the Open Dynamics Engine: ODE rigid bodies become colliders and attachment
 * points of a cloth, and contact reactions go back to the bodies. It follows
 * ODE's own style: dCloth prefix, dClothID handles, dReal at the boundary.
 *
 * For now it holds only the version query; the plugin API (dClothCreate,
 * dClothStep, ...) arrives with the plugin issue.
 */
#ifndef ODECLOTH_DCLOTH_H
#define ODECLOTH_DCLOTH_H

#include <ode/ode.h>

/* The cloth core: the plugin steps a core cloth, whose types it shares. */
#include "odecloth/cloth.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The odecloth version, "major.minor.patch" (the core's cloth_version()).
 * Never NULL; the string is static. */
const char *dClothGetVersion(void);

#ifdef __cplusplus
}
#endif

#endif /* ODECLOTH_DCLOTH_H */
