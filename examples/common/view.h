/* --view: watch a demo's run live in a window (GLFW + OpenGL), like ODE's
 * drawstuff demos. The window draws the scene demo_render draws (the same
 * demo_draw_scene, render.c) from an orbit camera that starts at the demo's
 * camera, with a text overlay (time, step, alpha, the step's CG iterations,
 * strain, contacts, plastic links, penetration).
 *
 * Mouse: left-drag rotates about the target, right-drag (up / down) or the
 * wheel zooms, middle-drag pans. Keys: space pauses and resumes, n or .
 * takes one step while paused (and pauses while running), f toggles real
 * time / as fast as it can, r puts the camera back, s saves the window as
 * <out>/view_NNN.png, q or Esc closes the window. At the last step of each
 * run the view pauses on it (space goes on).
 *
 * Closing the window does not stop the demo: it runs on headless to its
 * end, with its pictures, metrics, checks and exit status as without
 * --view. The view only reads the scene (positions, geoms, the step's
 * stats), so a run with --view is the run without it (test/demo_view.c
 * compares every step's printed stats, the metrics and the pictures).
 *
 * --view-frames N (scripted runs, tests): every step is drawn, with no
 * real-time pacing and no pauses; after N frames the window is written to
 * <out>/view.png and closed, and the demo runs on headless.
 *
 * No display (DISPLAY and WAYLAND_DISPLAY unset, or glfwInit or
 * glfwCreateWindow failing) or a build without GLFW: one line saying so,
 * then the demo runs headless, exit status unchanged.
 */
#ifndef ODECLOTH_EXAMPLES_VIEW_H
#define ODECLOTH_EXAMPLES_VIEW_H

#include "demo.h"

/* The per-step hook of a demo's simulation loop: call it after each step
 * (step: 1-based, of total in this run; label: the run's, e.g. "alpha 0.8";
 * cam: the demo's camera for the run). Without --view it returns at once.
 * With it, the first call opens the window (or says why not); then each
 * call polls events and draws (at most 60 frames a second, holding the run
 * to real time unless f was pressed), and blocks while paused. */
void demo_view_frame(const demo_opts *o, const char *label, int step, int total, const demo_camera *cam, dSpaceID space,
                     dClothID *cloths, int n);

#endif
