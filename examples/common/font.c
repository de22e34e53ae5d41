/* Labels in demo images: text in a TrueType font (DejaVu Sans unless the
 * environment's ODECLOTH_FONT names another .ttf), rendered anti-aliased by
 * FreeType. Without FreeType or the font, labels are left out, said once. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "demo.h"

#ifdef ODECLOTH_HAVE_FREETYPE
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_TRUETYPE_TABLES_H

#ifndef ODECLOTH_FONT_FILE /* the build names the file it found */
#define ODECLOTH_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#endif

static FT_Library library;
static FT_Face face;
static int loaded; /* 0: not tried yet, 1: face ready, -1: none (said so) */

static void close_font(void)
{
    FT_Done_Face(face);
    FT_Done_FreeType(library);
}

/* The face, loaded at the first label; NULL when there is none. */
static FT_Face font_face(void)
{
    if (loaded) return loaded > 0 ? face : NULL;
    const char *path = getenv("ODECLOTH_FONT");
    if (!path || !*path) path = ODECLOTH_FONT_FILE;
    loaded = -1;
    if (FT_Init_FreeType(&library)) {
        fprintf(stderr, "labels: FreeType did not start: pictures without labels\n");
        return NULL;
    }
    if (FT_New_Face(library, path, 0, &face)) {
        fprintf(stderr,
                "labels: cannot load the font %s (Debian: fonts-dejavu-core, or name a .ttf in "
                "ODECLOTH_FONT): pictures without labels\n",
                path);
        FT_Done_FreeType(library);
        return NULL;
    }
    loaded = 1;
    atexit(close_font);
    return face;
}

/* The face at the size whose capitals are 7 * scale pixels tall. */
static FT_Face sized_face(int scale)
{
    FT_Face f = font_face();
    if (!f || scale < 1) return NULL;
    const TT_OS2 *os2 = FT_Get_Sfnt_Table(f, FT_SFNT_OS2);
    double cap = os2 && os2->sCapHeight > 0 ? (double)os2->sCapHeight / f->units_per_EM : 0.73;
    return FT_Set_Pixel_Sizes(f, 0, (FT_UInt)(7.0 * scale / cap + 0.5)) ? NULL : f;
}

/* Lays out s (one byte a character) from pen 0: each glyph's pen position
 * in 26.6 pixels through draw (NULL: none); returns the advance in pixels. */
static int lay_out(FT_Face f, const char *s, FT_Int32 load, void (*draw)(void *, FT_Face, long), void *ctx)
{
    long pen = 0;
    FT_UInt prev = 0;
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        FT_UInt g = FT_Get_Char_Index(f, *p);
        if (prev && g && FT_HAS_KERNING(f)) {
            FT_Vector k;
            if (!FT_Get_Kerning(f, prev, g, FT_KERNING_DEFAULT, &k)) pen += k.x;
        }
        if (FT_Load_Glyph(f, g, load)) continue;
        if (draw) draw(ctx, f, pen);
        pen += f->glyph->advance.x;
        prev = g;
    }
    return (int)((pen + 32) >> 6);
}

typedef struct ink_at {
    demo_image *im;
    int x, baseline;
    const unsigned char *rgb;
} ink_at;

/* Blends the rendered glyph into the image, its coverage as opacity. */
static void draw_glyph(void *ctx, FT_Face f, long pen)
{
    const ink_at *t = ctx;
    const FT_Bitmap *b = &f->glyph->bitmap;
    if (b->pixel_mode != FT_PIXEL_MODE_GRAY) return; /* a font's embedded 1-bit bitmap: not coverage bytes */
    int x0 = t->x + (int)((pen + 32) >> 6) + f->glyph->bitmap_left, y0 = t->baseline - f->glyph->bitmap_top;
    for (int r = 0; r < (int)b->rows; r++)
        for (int c = 0; c < (int)b->width; c++) {
            int x = x0 + c, y = y0 + r, a = b->buffer[r * b->pitch + c];
            if (!a || x < 0 || y < 0 || x >= t->im->w || y >= t->im->h) continue;
            unsigned char *px = t->im->rgb + 3 * ((size_t)y * (size_t)t->im->w + (size_t)x);
            for (int k = 0; k < 3; k++) px[k] = (unsigned char)((px[k] * (255 - a) + t->rgb[k] * a + 127) / 255);
        }
}

int demo_text_width(int scale, const char *s)
{
    FT_Face f = sized_face(scale);
    return f ? lay_out(f, s, FT_LOAD_DEFAULT, NULL, NULL) : 0;
}

int demo_text(demo_image *im, int x, int y, int scale, const unsigned char rgb[3], const char *s)
{
    FT_Face f = sized_face(scale);
    if (!f) return 0;
    ink_at t = {im, x, y + 7 * scale, rgb};
    return lay_out(f, s, FT_LOAD_RENDER | FT_LOAD_NO_BITMAP, draw_glyph, &t);
}

#else /* no FreeType */

static void say_no_labels(void)
{
    static int said;
    if (!said) fprintf(stderr, "labels: built without FreeType (libfreetype-dev): pictures without labels\n");
    said = 1;
}

int demo_text_width(int scale, const char *s)
{
    (void)scale;
    (void)s;
    say_no_labels();
    return 0;
}

int demo_text(demo_image *im, int x, int y, int scale, const unsigned char rgb[3], const char *s)
{
    (void)im;
    (void)x;
    (void)y;
    (void)rgb;
    return demo_text_width(scale, s);
}

#endif
