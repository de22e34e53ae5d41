/* RGB images: a PNG writer (libpng, when built with it), a 5x7 bitmap font
 * for labels (upper case, digits and common punctuation; lower case is drawn
 * as upper case) and a contact-sheet composer. */
#include <ctype.h>
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

/* ------------------------------------------------------------------ font */

typedef struct glyph {
    char ch;
    unsigned char rows[7]; /* 5 bits a row, bit 4 the leftmost dot */
} glyph;

static const glyph font[] = {
    {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},
    {'0', {0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e}},
    {'1', {0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e}},
    {'2', {0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f}},
    {'3', {0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e}},
    {'4', {0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02}},
    {'5', {0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e}},
    {'6', {0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e}},
    {'7', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e}},
    {'9', {0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c}},
    {'A', {0x0e, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11}},
    {'B', {0x1e, 0x11, 0x11, 0x1e, 0x11, 0x11, 0x1e}},
    {'C', {0x0e, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0e}},
    {'D', {0x1c, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1c}},
    {'E', {0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f}},
    {'F', {0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x10}},
    {'G', {0x0e, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0f}},
    {'H', {0x11, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11}},
    {'I', {0x0e, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0c}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1f}},
    {'M', {0x11, 0x1b, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e}},
    {'P', {0x1e, 0x11, 0x11, 0x1e, 0x10, 0x10, 0x10}},
    {'Q', {0x0e, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0d}},
    {'R', {0x1e, 0x11, 0x11, 0x1e, 0x14, 0x12, 0x11}},
    {'S', {0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e}},
    {'T', {0x1f, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0a, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0a}},
    {'X', {0x11, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0a, 0x04, 0x04, 0x04}},
    {'Z', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1f}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0c, 0x04, 0x08}},
    {':', {0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x0c, 0x00}},
    {';', {0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x04, 0x08}},
    {'=', {0x00, 0x00, 0x1f, 0x00, 0x1f, 0x00, 0x00}},
    {'-', {0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1f}},
    {'\'', {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}},
    {'<', {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}},
    {'>', {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}},
    {'*', {0x00, 0x04, 0x15, 0x0e, 0x15, 0x04, 0x00}},
    {'?', {0x0e, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
    {'!', {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}},
    {'[', {0x0e, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0e}},
    {']', {0x0e, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0e}},
    {'#', {0x0a, 0x0a, 0x1f, 0x0a, 0x1f, 0x0a, 0x0a}},
    {'"', {0x0a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00}},
};

static const glyph *find_glyph(int ch)
{
    ch = toupper(ch);
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].ch == ch) return &font[i];
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].ch == '?') return &font[i];
    return NULL;
}

int demo_text_width(int scale, const char *s) { return (int)strlen(s) * 6 * scale - (*s ? scale : 0); }

static void put_pixel(demo_image *im, int x, int y, const unsigned char rgb[3])
{
    if (x < 0 || y < 0 || x >= im->w || y >= im->h) return;
    memcpy(im->rgb + 3 * ((size_t)y * (size_t)im->w + (size_t)x), rgb, 3);
}

int demo_text(demo_image *im, int x, int y, int scale, const unsigned char rgb[3], const char *s)
{
    for (int k = 0; s[k]; k++) {
        const glyph *g = find_glyph((unsigned char)s[k]);
        for (int r = 0; g && r < 7; r++)
            for (int c = 0; c < 5; c++)
                if (g->rows[r] & (0x10 >> c))
                    for (int dy = 0; dy < scale; dy++)
                        for (int dx = 0; dx < scale; dx++)
                            put_pixel(im, x + (6 * k + c) * scale + dx, y + r * scale + dy, rgb);
    }
    return demo_text_width(scale, s);
}

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
