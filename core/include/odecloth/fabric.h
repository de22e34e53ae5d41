/*
 * odecloth core: fabrics in physical units, independent of the grid.
 *
 * A cloth_material holds per-link stiffnesses, which mean a different
 * fabric at every grid spacing. A cloth_fabric describes the fabric itself
 * (what a textile lab measures) and cloth_fabric_material derives the
 * links' material for a given spacing:
 *
 *   cloth_desc d = cloth_default_desc();
 *   d.rows = d.cols = 41;
 *   cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
 *   if (cloth_fabric_apply(&f, &d, &err) != CLOTH_OK) ...;  // d.material set
 *
 * The derivation (docs/materials.md), for cells dx x dy (square cells are
 * what it is made for; others get the mean of the two thread directions and
 * bend very differently along them):
 *   - interlaced links: an interlaced link measures bending by the
 *     shortening of its chord, which is quadratic in the curvature kappa,
 *     so a bent sheet stores Q kappa^4 per unit area, not B kappa^2 / 2 at
 *     every curvature. k_b is chosen so that the two agree at kappa_ref
 *     (bend_curvature; by default eta / c, c the bending length
 *     (B / (density g0))^(1/3), g0 = CLOTH_FABRIC_GRAVITY, and eta = 1.1349
 *     such that the model's cantilever droops to ASTM D1388's 41.5 degrees
 *     at an overhang of 2 c, as a fabric of bending length c does). Q does
 *     not depend on the spacing: the bending is the same at every
 *     resolution and every curvature. The energy counted is that of a sheet
 *     free to relax in its plane (the shortened interlaced links push it
 *     apart). k_s = spreading k_b.
 *   - sequential links: the interlaced links stretch like a membrane too,
 *     so k_t + 4 k_b gives the membrane stiffness `tensile` along a thread
 *     direction with the other held (uniaxial strain; square cells:
 *     k_t + 4 k_b = tensile / 2). k_c = compression k_t.
 *   - k_b grows as the spacing^-4, so below a spacing the fabric's bending
 *     cannot be had within its tensile stiffness (the interlaced links would
 *     carry more than half of it): refused, the message naming the finest
 *     spacing (cotton's preset: about 3 mm).
 *   - damping: Kelvin-Voigt time constants, c_t = tau_tension k_t and
 *     c_b = tau_bending k_b, so the damping scales with the stiffness it
 *     damps and is grid-independent like it.
 *   - alpha, delta, k_delta, density, the time-dependent plastic law's
 *     tau_set, tau_recover, set_hardening (seconds and a ratio: the same
 *     at every spacing) and the tension plasticity's tension_yield,
 *     tension_set (ratios) are passed through; plastic_memory is 0.
 *   - the crease law's k_crease = 4 crease_stiffness / h (the mean of
 *     4 S dy / dx^2 and 4 S dx / dy^2): a moment per length of crease, the
 *     same at every grid (docs/materials.md, "The crease law").
 */
#ifndef ODECLOTH_FABRIC_H
#define ODECLOTH_FABRIC_H

#include "cloth.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What cloth_fabric_bending_length and the default kappa_ref use (m/s^2). */
#define CLOTH_FABRIC_GRAVITY 9.81

typedef struct cloth_fabric {
    double tensile;          /* N/m   > 0: membrane stiffness along a thread
                                    direction, the cross direction held
                                    (stress per unit width / strain)       */
    double bending;          /* N m   > 0: bending rigidity B per unit width
                                    (KES-F B; ASTM D1388: B = w g c^3)     */
    double density;          /* kg/m^2 > 0: weight per area                  */
    double compression;      /* 1     > 0: k_c / k_t, compression softness   */
    double alpha;            /* 1     in [0, 1]: plastic yield ratio d/l0 of
                                    the interlaced links (0 = elastic)     */
    double spreading;        /* 1     >= 0: k_s / k_b                        */
    double delta;            /* 1     > 0: elongation limit                  */
    double k_delta;          /* 1     >= 0: stiffening past the limit, as
                                    cloth_material.k_delta                 */
    double tau_tension;      /* s     >= 0: c_t = tau_tension k_t            */
    double tau_bending;      /* s     >= 0: c_b = tau_bending k_b            */
    double bend_curvature;   /* 1/m   >= 0: kappa_ref, where the bending
                                    energy equals B kappa^2 / 2; 0 = the
                                    cantilever's, eta / bending length     */
    double tau_set;          /* s     >= 0: passed through (cloth_material's
                                    time-dependent plastic law; 0 in the
                                    presets: the paper's rule)             */
    double tau_recover;      /* s     >= 0: passed through, likewise         */
    double set_hardening;    /* 1     in [0, 1]: passed through, likewise    */
    double tension_yield;    /* 1     in [0, delta]: passed through (cloth_material's
                                    tension plasticity; 0 in the presets: off) */
    double tension_set;      /* 1     in [0, 1]: passed through, likewise    */
    double crease_stiffness; /* N (N m/m per radian) >= 0: the crease law's
                                    moment per length of crease per radian
                                    near flat; 0 = off (the presets)       */
} cloth_fabric;

typedef enum cloth_fabric_kind {
    CLOTH_FABRIC_COTTON = 0, /* plain-weave shirting                */
    CLOTH_FABRIC_WOOL,       /* woollen flannel                     */
    CLOTH_FABRIC_SILK,       /* crepe de chine                      */
    CLOTH_FABRIC_DENIM,      /* 3/1 cotton twill, jeans weight      */
    CLOTH_FABRIC_POLYESTER   /* plain-weave filament dress fabric   */
} cloth_fabric_kind;

/* A preset's values (sources and estimates: docs/materials.md); an unknown
 * kind gives cotton. The presets are not the defaults of cloth_desc. */
ODECLOTH_API cloth_fabric cloth_fabric_preset(cloth_fabric_kind k);

/* CLOTH_OK or CLOTH_EINVAL with a message naming the field (err may be NULL). */
ODECLOTH_API cloth_status cloth_fabric_validate(const cloth_fabric *f, cloth_error *err);

/* The links' material for cells of dx x dy m (a cloth_desc's
 * width / (cols - 1) and height / (rows - 1)). On error *out is untouched
 * and err says which field or spacing is at fault. */
ODECLOTH_API cloth_status cloth_fabric_material(const cloth_fabric *f, double dx, double dy, cloth_material *out,
                                                cloth_error *err);

/* d->material = cloth_fabric_material(f, d's dx, d's dy); d untouched on error. */
ODECLOTH_API cloth_status cloth_fabric_apply(const cloth_fabric *f, cloth_desc *d, cloth_error *err);

/* c = (bending / (density CLOTH_FABRIC_GRAVITY))^(1/3), m: ASTM D1388's
 * bending length. NaN for a fabric that does not validate. */
ODECLOTH_API double cloth_fabric_bending_length(const cloth_fabric *f);

/* kappa_ref (1/m): bend_curvature, or eta / bending length if it is 0.
 * NaN for a fabric that does not validate. */
ODECLOTH_API double cloth_fabric_reference_curvature(const cloth_fabric *f);

#ifdef __cplusplus
}
#endif
#endif
