/* Pictures of a cloth scene with the fixed-function OpenGL pipeline: one
 * scene-drawing function (demo_draw_scene) used by the offscreen renderer
 * here (OSMesa, which ships a GL 2.1 compatibility context) and by the
 * --view window (view.c: GLFW's context on the system's libGL).
 *
 * Three passes over the geometry (draw.c): the casters (geoms but planes,
 * cloths) into a shadow map from the key light (shadow.c); the scene lit
 * by the ambient and the fill light; the key light's share added on top,
 * scaled by the map's lookup, so what the light cannot reach keeps the
 * ambient and fill only; then the floor darkened where a cloth touches or
 * nears it (contact.c). Offscreen pictures are rendered at twice the size
 * and averaged down 2x2 (antialiasing). */
#include <stdlib.h>
#include <string.h>
#include "contact.h"
#include "shadow.h"

const float demo_geom_hidden[3] = {0, 0, 0};
const double demo_key_light[3] = {-0.35, -0.55, 1.0};

#ifdef ODECLOTH_HAVE_OSMESA
#include <GL/osmesa.h>
#endif
#ifdef DEMO_HAVE_GL

static void set_lights(int key, int ambient_fill)
{
    GLfloat amb[4] = {0.22f, 0.22f, 0.24f, 1}, none[4] = {0, 0, 0, 1};
    GLfloat key_pos[4] = {(float)demo_key_light[0], (float)demo_key_light[1], (float)demo_key_light[2], 0};
    GLfloat fill_pos[4] = {0.6f, 0.4f, 0.35f, 0};
    GLfloat key_d[4] = {0.75f, 0.75f, 0.72f, 1}, fill_d[4] = {0.28f, 0.28f, 0.32f, 1};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient_fill ? amb : none);
    glLightfv(GL_LIGHT0, GL_POSITION, key_pos);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, key_d);
    glLightfv(GL_LIGHT0, GL_SPECULAR, none);
    glLightfv(GL_LIGHT1, GL_POSITION, fill_pos);
    glLightfv(GL_LIGHT1, GL_DIFFUSE, fill_d);
    glLightfv(GL_LIGHT1, GL_SPECULAR, none);
    if (key) glEnable(GL_LIGHT0);
    else glDisable(GL_LIGHT0);
    if (ambient_fill) glEnable(GL_LIGHT1);
    else glDisable(GL_LIGHT1);
}

static void draw_all(dSpaceID space, const demo_camera *cam, const draw_mesh *m, int n, int casters_only)
{
    draw_geoms(space, cam, casters_only);
    for (int i = 0; i < n; i++) draw_mesh_triangles(&m[i]);
}

/* The depth pass; 0 with the map made, -1 if there is nothing to cast. */
static int make_shadow(shadow_map *sm, dSpaceID space, const demo_camera *cam, const draw_mesh *m, int n, int w, int h)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    draw_bounds(space, m, n, lo, hi);
    int size = w < h ? w : h;
    if (size > 2048) size = 2048;
    if (shadow_begin(sm, demo_key_light, lo, hi, size)) return -1;
    draw_all(space, cam, m, n, 1);
    shadow_end(sm);
    return 0;
}

static void camera(const demo_camera *cam, int w, int h)
{
    glViewport(0, 0, w, h);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double zn = 0.05, zf = 50, top = zn * tan(cam->fov_deg * M_PI / 360), right = top * w / h;
    glFrustum(-right, right, -top, top, zn, zf);
    glMatrixMode(GL_MODELVIEW);
    draw_look_at(cam->eye, cam->target);
}

int demo_draw_scene(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w, int h)
{
    draw_mesh *m = calloc(ncloths > 0 ? (size_t)ncloths : 1, sizeof *m);
    int ok = m != NULL;
    for (int i = 0; ok && i < ncloths; i++) ok = !draw_mesh_build(&m[i], cloths[i], smooth);
    if (!ok) {
        for (int i = 0; m && i < ncloths; i++) draw_mesh_free(&m[i]);
        free(m);
        fprintf(stderr, "render: out of memory for the cloth mesh\n");
        return -1;
    }
    glDisable(GL_BLEND);
    glDisable(GL_TEXTURE_2D);
    shadow_map sm;
    int shadows = !make_shadow(&sm, space, cam, m, ncloths, w, h);
    glClearColor(0.93f, 0.95f, 0.98f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_LIGHTING);
    glEnable(GL_NORMALIZE);
    glShadeModel(GL_SMOOTH);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    camera(cam, w, h);
    set_lights(!shadows, 1); /* lights are placed in the world: after the camera */
    draw_all(space, cam, m, ncloths, 0);
    if (shadows) {
        /* the key light's share where it reaches: added onto the same depths */
        set_lights(1, 0);
        shadow_bind(&sm);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glDepthMask(GL_FALSE);
        /* a few depth units forward: the texgen pass may round depth apart */
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(0.0f, -4.0f);
        draw_all(space, cam, m, ncloths, 0);
        glDisable(GL_POLYGON_OFFSET_FILL);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
        shadow_unbind();
        shadow_free(&sm);
    }
    contact_shade(space, m, ncloths);
    for (int i = 0; i < ncloths; i++) draw_mesh_free(&m[i]);
    free(m);
    return 0;
}
#endif /* DEMO_HAVE_GL */

/* ------------------------------------------------------- offscreen (OSMesa) */

#ifdef ODECLOTH_HAVE_OSMESA

static OSMesaContext ctx;
static unsigned char *buffer;
static int buf_w, buf_h;
static char failure[160];

int demo_render_available(void) { return 1; }
const char *demo_render_unavailable_reason(void) { return failure; }

void demo_render_shutdown(void)
{
    if (ctx) OSMesaDestroyContext(ctx);
    ctx = NULL;
    free(buffer);
    buffer = NULL;
    buf_w = buf_h = 0;
}

static int ensure_context(int w, int h)
{
    if (!ctx) {
        ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
        if (!ctx) {
            snprintf(failure, sizeof failure, "OSMesaCreateContextExt failed");
            return -1;
        }
    }
    if (w != buf_w || h != buf_h) {
        unsigned char *b = realloc(buffer, 4 * (size_t)w * (size_t)h);
        if (!b) {
            snprintf(failure, sizeof failure, "out of memory for a %d x %d frame", w, h);
            return -1;
        }
        buffer = b;
        buf_w = w;
        buf_h = h;
    }
    if (!OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, w, h)) {
        snprintf(failure, sizeof failure, "OSMesaMakeCurrent failed for %d x %d", w, h);
        return -1;
    }
    return 0;
}

demo_image *demo_render(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w, int h)
{
    const int ss = 2; /* supersampling */
    if (w <= 0 || h <= 0 || ensure_context(ss * w, ss * h)) {
        if (w <= 0 || h <= 0) snprintf(failure, sizeof failure, "bad picture size %d x %d", w, h);
        fprintf(stderr, "render: %s\n", failure);
        return NULL;
    }
    int W = ss * w, H = ss * h;
    if (demo_draw_scene(cam, space, cloths, ncloths, smooth, W, H)) return NULL;
    glFinish();
    static const unsigned char bg[3] = {255, 255, 255};
    demo_image *im = demo_image_create(w, h, bg);
    if (!im) {
        fprintf(stderr, "render: out of memory for a %d x %d image\n", w, h);
        return NULL;
    }
    /* OSMesa's row 0 is the bottom; average ss x ss blocks */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                int sum = 0;
                for (int dy = 0; dy < ss; dy++)
                    for (int dx = 0; dx < ss; dx++)
                        sum += buffer[4 * ((size_t)(H - 1 - (ss * y + dy)) * W + (size_t)(ss * x + dx)) + k];
                im->rgb[3 * ((size_t)y * w + x) + k] = (unsigned char)((sum + ss * ss / 2) / (ss * ss));
            }
    return im;
}

#else /* no OSMesa: metrics only */

int demo_render_available(void) { return 0; }
const char *demo_render_unavailable_reason(void)
{
    return "built without OSMesa (install libosmesa6-dev and rebuild): no pictures, metrics only";
}
void demo_render_shutdown(void) {}

demo_image *demo_render(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w, int h)
{
    (void)cam, (void)space, (void)cloths, (void)ncloths, (void)smooth, (void)w, (void)h;
    fprintf(stderr, "render: %s\n", demo_render_unavailable_reason());
    return NULL;
}
#endif
