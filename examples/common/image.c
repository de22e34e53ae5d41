/* RGB images: a PNG writer (libpng, when built with it), copying one image
 * into another and a contact-sheet composer (labels: font.c). */
#include <stdlib.h>
#include <string.h>
#include "demo.h"
#ifdef ODECLOTH_HAVE_PNG
#include <png.h>
#endif

demo_image *demo_image_create(int w, int h, const unsigned char bg[3])
{
    if (w <= 0 || h <= 0) return NULL;
    demo_image *im = malloc(sizeof *im);
    if (!im) return NULL;
    im->w = w;
    im->h = h;
    im->rgb = malloc(3 * (size_t)w * (size_t)h);
    if (!im->rgb) {
        free(im);
        return NULL;
    }
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) memcpy(im->rgb + 3 * i, bg, 3);
    return im;
}

void demo_image_destroy(demo_image *im)
{
    if (!im) return;
    free(im->rgb);
    free(im);
}

#ifdef ODECLOTH_HAVE_PNG
int demo_png_available(void) { return 1; }

int demo_png_write(const char *path, const demo_image *im)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        return -1;
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep *rows = malloc((size_t)im->h * sizeof *rows);
    if (!png || !info || !rows) {
        fprintf(stderr, "%s: out of memory for the PNG writer\n", path);
        png_destroy_write_struct(&png, info ? &info : NULL);
        free(rows);
        fclose(f);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "%s: libpng failed to write the image\n", path);
        png_destroy_write_struct(&png, &info);
        free(rows);
        fclose(f);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)im->w, (png_uint_32)im->h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 9);
    png_write_info(png, info);
    for (int y = 0; y < im->h; y++) rows[y] = im->rgb + 3 * (size_t)im->w * (size_t)y;
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(rows);
    if (fclose(f)) {
        perror(path);
        return -1;
    }
    return 0;
}
#else
int demo_png_available(void) { return 0; }

int demo_png_write(const char *path, const demo_image *im)
{
    (void)im;
    fprintf(stderr, "%s: not written: built without libpng (install libpng-dev and rebuild)\n", path);
    return -1;
}
#endif

void demo_blit(demo_image *dst, const demo_image *src, int x, int y)
{
    for (int r = 0; r < src->h; r++) {
        int yy = y + r;
        if (yy < 0 || yy >= dst->h) continue;
        int c0 = x < 0 ? -x : 0, c1 = x + src->w > dst->w ? dst->w - x : src->w;
        if (c1 <= c0) continue;
        memcpy(dst->rgb + 3 * ((size_t)yy * (size_t)dst->w + (size_t)(x + c0)),
               src->rgb + 3 * ((size_t)r * (size_t)src->w + (size_t)c0), 3 * (size_t)(c1 - c0));
    }
}

/* ---------------------------------------------------------- contact sheet */

demo_image *demo_contact_sheet(const demo_image *const *cells, int rows, int cols, const char *const *row_labels,
                               const char *const *col_labels, const char *title)
{
    static const unsigned char white[3] = {255, 255, 255}, ink[3] = {20, 20, 30};
    const int scale = 2, pad = 8, line = 7 * scale;
    int cw = 0, ch = 0, label_w = 0;
    for (int i = 0; i < rows * cols; i++)
        if (cells[i]) {
            if (cells[i]->w > cw) cw = cells[i]->w;
            if (cells[i]->h > ch) ch = cells[i]->h;
        }
    if (!cw) cw = ch = 64;
    for (int r = 0; r < rows; r++)
        if (row_labels && row_labels[r] && demo_text_width(scale, row_labels[r]) > label_w)
            label_w = demo_text_width(scale, row_labels[r]);
    int top = pad + (title ? line + pad : 0) + (col_labels ? line + pad : 0);
    int left = pad + (label_w ? label_w + pad : 0);
    int W = left + cols * (cw + pad), H = top + rows * (ch + pad);
    demo_image *s = demo_image_create(W, H, white);
    if (!s) return NULL;
    if (title) demo_text(s, pad, pad, scale, ink, title);
    for (int c = 0; c < cols; c++)
        if (col_labels && col_labels[c]) {
            int x = left + c * (cw + pad) + (cw - demo_text_width(scale, col_labels[c])) / 2;
            demo_text(s, x, top - line - pad / 2, scale, ink, col_labels[c]);
        }
    for (int r = 0; r < rows; r++) {
        int y = top + r * (ch + pad);
        if (row_labels && row_labels[r]) demo_text(s, pad, y + (ch - line) / 2, scale, ink, row_labels[r]);
        for (int c = 0; c < cols; c++)
            if (cells[r * cols + c]) demo_blit(s, cells[r * cols + c], left + c * (cw + pad), y);
    }
    return s;
}
