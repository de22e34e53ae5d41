/* Cloth triangles against a trimesh (mesh_contacts.c). */
#ifndef ODECLOTH_MESH_CONTACTS_H
#define ODECLOTH_MESH_CONTACTS_H

#include <ccd/ccd.h>
#include "dcloth_internal.h"
#include "triangle_query.h"

/* The trimesh q->g's triangles, as prisms, against the cloth triangles near them over the step of h
 * seconds (q: the geom's query, its shape set here; ccd, fine: libccd's loose and tight queries, their
 * first shape set here); the vertex contacts set (none when memory ran out) */
int dcloth_mesh_contacts(dClothID c, convex_query *q, double h, ccd_t *ccd, ccd_t *fine);

#endif
