/* --view: the live window (view.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "view.h"

#ifndef ODECLOTH_HAVE_GLFW

void demo_view_frame(const demo_opts *o, const char *label, int step, int total, const demo_camera *cam, dSpaceID space,
                     dClothID *cloths, int n)
{
    static int said;
    (void)label, (void)step, (void)total, (void)cam, (void)space, (void)cloths, (void)n;
    if (!o->view || said) return;
    said = 1;
    printf("%s: --view: built without GLFW (install libglfw3-dev and rebuild); running headless\n", o->prog);
}

#else

#include <GLFW/glfw3.h>

#define FRAME_SECONDS (1.0 / 60.0) /* draw at most this often (interactive) */

/* Everything the window needs between calls: there is one window a
 * process, kept across the demo's runs. */
static struct {
    int given_up; /* no display, or the window was closed: headless on  */
    GLFWwindow *win;
    char error[200]; /* GLFW's last error, for the message                 */
    /* the run being shown */
    const demo_opts *o;
    char label[64];
    int step, total;
    dSpaceID space;
    dClothID *cloths;
    int n;
    double anchor; /* wall time at which this run's simulated time was 0 */
    double last_draw;
    long frames;
    int shots;
    /* user state */
    int paused, step_once, fast, quit, shot, at_end;
    /* orbit camera: eye = target + dist (cos el cos az, cos el sin az, sin el) */
    demo_camera demo_cam; /* the demo's, for r; a new one resets the orbit */
    int have_cam;
    double az, el, dist, target[3];
    int buttons; /* bit 0 left, 1 right, 2 middle */
    double mx, my;
} V;

static void on_error(int code, const char *what)
{
    snprintf(V.error, sizeof V.error, "%s (GLFW error 0x%x)", what ? what : "?", code);
}

static void at_exit(void)
{
    if (V.win) glfwDestroyWindow(V.win);
    V.win = NULL;
    glfwTerminate();
}

/* ---------------------------------------------------------------- camera */

static void reset_orbit(void)
{
    const demo_camera *c = &V.demo_cam;
    double d[3] = {c->eye[0] - c->target[0], c->eye[1] - c->target[1], c->eye[2] - c->target[2]};
    V.dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(V.dist > 1e-6)) V.dist = 1.0, d[0] = 1.0, d[1] = d[2] = 0.0;
    V.az = atan2(d[1], d[0]);
    V.el = asin(fmax(-1.0, fmin(1.0, d[2] / V.dist)));
    memcpy(V.target, c->target, sizeof V.target);
}

static demo_camera orbit_camera(void)
{
    demo_camera c;
    double ce = cos(V.el);
    c.eye[0] = V.target[0] + V.dist * ce * cos(V.az);
    c.eye[1] = V.target[1] + V.dist * ce * sin(V.az);
    c.eye[2] = V.target[2] + V.dist * sin(V.el);
    memcpy(c.target, V.target, sizeof c.target);
    c.fov_deg = V.demo_cam.fov_deg;
    return c;
}

static void zoom(double factor) { V.dist = fmin(100.0, fmax(0.05, V.dist * factor)); }

/* -------------------------------------------------------------- callbacks */

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)w, (void)scancode, (void)mods;
    if (action == GLFW_RELEASE) return;
    if (action == GLFW_REPEAT && key != GLFW_KEY_N && key != GLFW_KEY_PERIOD) return;
    switch (key) {
    case GLFW_KEY_SPACE: V.paused = !V.paused; break;
    case GLFW_KEY_N:
    case GLFW_KEY_PERIOD:
        if (V.paused) V.step_once = 1;
        else V.paused = 1;
        break;
    case GLFW_KEY_F: V.fast = !V.fast; break;
    case GLFW_KEY_R: reset_orbit(); break;
    case GLFW_KEY_S: V.shot = 1; break;
    case GLFW_KEY_Q:
    case GLFW_KEY_ESCAPE: V.quit = 1; break;
    default: break;
    }
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    int bit = button == GLFW_MOUSE_BUTTON_LEFT     ? 1
              : button == GLFW_MOUSE_BUTTON_RIGHT  ? 2
              : button == GLFW_MOUSE_BUTTON_MIDDLE ? 4
                                                   : 0;
    if (action == GLFW_PRESS) V.buttons |= bit;
    else V.buttons &= ~bit;
    glfwGetCursorPos(w, &V.mx, &V.my);
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    (void)w;
    double dx = x - V.mx, dy = y - V.my;
    V.mx = x;
    V.my = y;
    if (V.buttons & 1) {
        V.az -= 0.008 * dx;
        V.el = fmax(-1.55, fmin(1.55, V.el + 0.008 * dy));
    } else if (V.buttons & 2) {
        zoom(exp(0.01 * dy));
    } else if (V.buttons & 4) {
        /* along the screen's right and up directions, in proportion to
         * the distance (the target stays under the cursor, roughly) */
        double s = 0.0015 * V.dist;
        double right[3] = {-sin(V.az), cos(V.az), 0};
        double up[3] = {-sin(V.el) * cos(V.az), -sin(V.el) * sin(V.az), cos(V.el)};
        for (int k = 0; k < 3; k++) V.target[k] += s * (-dx * right[k] + dy * up[k]);
    }
}

static void on_scroll(GLFWwindow *w, double xoff, double yoff)
{
    (void)w, (void)xoff;
    zoom(exp(-0.1 * yoff));
}

/* ---------------------------------------------------------------- drawing */

/* The text overlay at the bottom left: the bitmap font of the contact sheets
 * (image.c) into an image, its background half transparent. */
static void draw_overlay(int W, int H)
{
    const int scale = W >= 700 ? 2 : 1, line = 9 * scale, pad = 4 * scale;
    char text[5][160];
    int nl = 0;
    const dClothStepStats *st = V.n > 0 ? dClothGetStats(V.cloths[0]) : NULL;
    double alpha = V.n > 0 ? cloth_get_desc(dClothGetCore(V.cloths[0])).material.alpha : 0.0;
    snprintf(text[nl++], sizeof text[0], "%s: %s", V.o->prog, V.label);
    int n = snprintf(text[nl], sizeof text[0], "t %.3f s  step %d / %d", V.step / V.o->hz, V.step, V.total);
    if (!strstr(V.label, "alpha")) /* the label says it, mostly */
        snprintf(text[nl] + n, sizeof text[0] - (size_t)n, "  alpha %g", alpha);
    nl++;
    if (st)
        snprintf(text[nl++], sizeof text[0], "CG %d  strain %.4f  contacts %d  plastic %d  pen %.2f mm%s",
                 st->core.iterations, st->core.max_strain, st->contacts, st->core.plastic_links,
                 1e3 * st->max_penetration, st->sleeping ? "  asleep" : "");
    if (V.o->view_frames) snprintf(text[nl++], sizeof text[0], "frame %ld of %d", V.frames + 1, V.o->view_frames);
    else if (V.at_end) snprintf(text[nl++], sizeof text[0], "end of run: space goes on, q closes");
    else if (V.paused) snprintf(text[nl++], sizeof text[0], "paused: space runs, n steps");
    else snprintf(text[nl++], sizeof text[0], "%s", V.fast ? "running, fast (f: real time)" : "running (f: fast)");
    snprintf(text[nl++], sizeof text[0], "drag turns, right/wheel zooms, middle pans; r s q");
    int w = 0;
    for (int i = 0; i < nl; i++) {
        int tw = demo_text_width(scale, text[i]);
        if (tw > w) w = tw;
    }
    w += 2 * pad;
    int h = nl * line + 2 * pad - 2 * scale;
    if (w > W - 8) w = W - 8;
    if (h > H - 8) h = H - 8;
    if (w <= 0 || h <= 0) return;
    static const unsigned char bg[3] = {250, 250, 252}, ink[3] = {30, 30, 40};
    demo_image *im = demo_image_create(w, h, bg);
    unsigned char *rgba = malloc(4 * (size_t)w * (size_t)h);
    if (!im || !rgba) {
        demo_image_destroy(im);
        free(rgba);
        return;
    }
    for (int i = 0; i < nl; i++) demo_text(im, pad, pad + i * line, scale, ink, text[i]);
    for (size_t p = 0; p < (size_t)w * (size_t)h; p++) {
        memcpy(rgba + 4 * p, im->rgb + 3 * p, 3);
        rgba[4 * p + 3] = memcmp(im->rgb + 3 * p, bg, 3) ? 255 : 170;
    }
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, W, 0, H, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDisable(GL_LIGHTING);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glRasterPos2i(8, 8 + h);  /* bottom left: mostly floor there */
    glPixelZoom(1.0f, -1.0f); /* the image's row 0 is its top */
    glDrawPixels(w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glPixelZoom(1.0f, 1.0f);
    glDisable(GL_BLEND);
    demo_image_destroy(im);
    free(rgba);
}

/* The back buffer, as drawn, to a PNG. */
static void save_window(int W, int H, const char *path)
{
    static const unsigned char black[3] = {0, 0, 0};
    demo_image *im = demo_image_create(W, H, black);
    unsigned char *px = malloc(3 * (size_t)W * (size_t)H);
    if (im && px) {
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, px);
        for (int y = 0; y < H; y++) /* GL's row 0 is the bottom */
            memcpy(im->rgb + 3 * (size_t)W * y, px + 3 * (size_t)W * (H - 1 - y), 3 * (size_t)W);
        if (!demo_png_write(path, im)) printf("  wrote %s\n", path);
    } else {
        fprintf(stderr, "%s: --view: out of memory for a %d x %d screenshot\n", V.o->prog, W, H);
    }
    demo_image_destroy(im);
    free(px);
}

static void draw(const char *shot_path)
{
    int W, H;
    /* The window's context is current only while it draws: OSMesa makes its own current in between, behind
     * libGL's (glvnd) back, which would take a second glXMakeCurrent of the same context for a no-op and leave
     * OSMesa's in place. */
    glfwGetFramebufferSize(V.win, &W, &H);
    V.last_draw = demo_now();
    if (W <= 0 || H <= 0) return; /* minimised */
    glfwMakeContextCurrent(V.win);
    demo_camera cam = orbit_camera();
    demo_draw_scene(&cam, V.space, V.cloths, V.n, V.o->smooth, W, H);
    draw_overlay(W, H);
    char path[1100];
    if (V.shot && !shot_path) {
        snprintf(path, sizeof path, "%s/view_%03d.png", V.o->out, ++V.shots);
        shot_path = path;
    }
    V.shot = 0;
    if (shot_path) save_window(W, H, shot_path);
    glfwSwapBuffers(V.win);
    glfwMakeContextCurrent(NULL);
}

/* ------------------------------------------------------------ the window */

static void give_up(const char *why)
{
    printf("%s: --view: %s; running headless\n", V.o->prog, why);
    V.given_up = 1;
}

static void close_window(const char *why)
{
    if (V.win) glfwDestroyWindow(V.win);
    V.win = NULL;
    V.given_up = 1;
    printf("%s: --view: %s; running on headless\n", V.o->prog, why);
}

static int open_window(void)
{
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    char why[300];
    if ((!x || !*x) && (!wl || !*wl)) {
        give_up("no display (DISPLAY and WAYLAND_DISPLAY unset)");
        return -1;
    }
    glfwSetErrorCallback(on_error);
    if (!glfwInit()) {
        snprintf(why, sizeof why, "no display (glfwInit failed: %s)", V.error);
        give_up(why);
        return -1;
    }
    atexit(at_exit);
    int W = 2 * V.o->width, H = 2 * V.o->height;
    if (W > 1600 || H > 1200) { /* the picture size's aspect, at most 1600 x 1200 */
        double s = fmin(1600.0 / W, 1200.0 / H);
        W = (int)(s * W);
        H = (int)(s * H);
    }
    char title[120];
    snprintf(title, sizeof title, "%s (odecloth)", V.o->prog);
    glfwWindowHint(GLFW_SAMPLES, 4);
    V.win = glfwCreateWindow(W, H, title, NULL, NULL);
    if (!V.win) { /* without multisampling, then */
        glfwWindowHint(GLFW_SAMPLES, 0);
        V.win = glfwCreateWindow(W, H, title, NULL, NULL);
    }
    if (!V.win) {
        snprintf(why, sizeof why, "no display (glfwCreateWindow failed: %s)", V.error);
        give_up(why);
        return -1;
    }
    glfwMakeContextCurrent(V.win);
    glfwSwapInterval(0); /* the pacing is ours */
    glfwMakeContextCurrent(NULL);
    glfwSetKeyCallback(V.win, on_key);
    glfwSetMouseButtonCallback(V.win, on_button);
    glfwSetCursorPosCallback(V.win, on_cursor);
    glfwSetScrollCallback(V.win, on_scroll);
    if (V.o->view_frames)
        printf("%s: --view: window %d x %d, closing after %d frames\n", V.o->prog, W, H, V.o->view_frames);
    else
        printf("%s: --view: window %d x %d (space pause, n step, f fast, r camera, s save, q close)\n", V.o->prog, W,
               H);
    fflush(stdout);
    return 0;
}

static int closing(void) { return V.quit || glfwWindowShouldClose(V.win); }

/* Paused: draw and wait for events until resumed, a step asked for, or
 * the window closed; t is the simulated time shown. */
static void hold(double t)
{
    while (V.paused && !V.step_once && !closing()) {
        draw(NULL);
        glfwWaitEventsTimeout(0.25);
    }
    V.at_end = 0;
    if (closing()) close_window("window closed");
    V.anchor = demo_now() - t; /* real time goes on from here */
}

void demo_view_frame(const demo_opts *o, const char *label, int step, int total, const demo_camera *cam, dSpaceID space,
                     dClothID *cloths, int n)
{
    if (!o->view || V.given_up) return;
    V.o = o;
    if (!V.win && open_window()) return;
    double t = step / o->hz;
    if (step <= V.step || total != V.total || strncmp(label, V.label, sizeof V.label - 1)) /* a new run */
        V.anchor = demo_now() - t;
    snprintf(V.label, sizeof V.label, "%s", label);
    V.step = step;
    V.total = total;
    V.space = space;
    V.cloths = cloths;
    V.n = n;
    if (!V.have_cam || memcmp(cam, &V.demo_cam, sizeof *cam)) { /* a new scene: its camera */
        V.demo_cam = *cam;
        V.have_cam = 1;
        reset_orbit();
    }
    glfwPollEvents();
    if (closing()) {
        close_window("window closed");
        return;
    }
    if (o->view_frames) { /* scripted: every step, no pacing, no pauses */
        char path[1100];
        int last = V.frames + 1 >= o->view_frames;
        if (last) snprintf(path, sizeof path, "%s/view.png", o->out);
        draw(last ? path : NULL);
        if (++V.frames >= o->view_frames) {
            char why[80];
            snprintf(why, sizeof why, "%ld frames shown, window closed", V.frames);
            close_window(why);
        }
        return;
    }
    if (V.step_once) { /* the one step asked for is done */
        V.step_once = 0;
        V.paused = 1;
    }
    if (step == total) V.paused = V.at_end = 1; /* hold the run's last frame */
    if (V.paused) {
        hold(t);
        return;
    }
    /* running: hold the run to real time (unless fast), a frame at most
     * every FRAME_SECONDS */
    for (;;) {
        double now = demo_now(), ahead = V.anchor + t - now;
        if (V.fast || ahead < -0.25) V.anchor = now - t; /* behind: no catching up */
        if (V.fast || ahead <= 0) break;
        if (now - V.last_draw >= FRAME_SECONDS) draw(NULL);
        glfwWaitEventsTimeout(fmin(ahead, FRAME_SECONDS));
        if (closing()) {
            close_window("window closed");
            return;
        }
        if (V.paused) {
            hold(t);
            return;
        }
    }
    if (demo_now() - V.last_draw >= FRAME_SECONDS || V.shot) draw(NULL);
}

#endif
