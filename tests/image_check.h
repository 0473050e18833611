/* image_check.h: what the image tests share: a small test image of distinct values in 8-bit and
 * float forms, their bit-exact comparison, and the temporary folder's entries. */
#ifndef TRAZADOR_IMAGE_CHECK_H
#define TRAZADOR_IMAGE_CHECK_H

#include <dirent.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "image/image.h"

static inline int count_entries(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
    closedir(d);
    return n;
}

static inline void remove_tree(const char *path) {
    struct stat st;
    if (lstat(path, &st) != 0) return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        for (struct dirent *e; d && (e = readdir(d));) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
            char child[1024];
            if (snprintf(child, sizeof child, "%s/%s", path, e->d_name) >= (int)sizeof child)
                continue; /* never in the tests' own folders */
            remove_tree(child);
        }
        if (d) closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

/* 6x5, every value distinct and encoding its row, column and channel. 8-bit images hold the
   decoded value of a distinct byte, so that an exact round trip is possible. */
enum { W = 6, H = 5 };

static inline uint8_t test_byte(int x, int y, int c) {
    return (uint8_t)(40 + 2 * ((y * W + x) * 3 + c));
}

static inline void make_8bit_image(image *img, tonemap tm) {
    image_init(img, W, H);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++)
                img->rgb[(y * W + x) * 3 + c] = tonemap_decode(test_byte(x, y, c), tm);
}

static inline float test_float(int x, int y, int c) {
    float scaled = (float)(y * 100 + x * 10 + c) * 0.37f; /* two statements: never fused */
    return scaled - 3.0f;
}

static inline void make_float_image(image *img) {
    image_init(img, W, H);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) img->rgb[(y * W + x) * 3 + c] = test_float(x, y, c);
}

/* Same size and bit-identical values; prints the first difference. */
static inline bool same_image(const image *got, const image *want) {
    if (got->width != want->width || got->height != want->height || !got->rgb) {
        printf("  %s: size %dx%d, want %dx%d\n", check_case_name, got->width, got->height,
               want->width, want->height);
        return false;
    }
    for (int i = 0; i < want->width * want->height * 3; i++) {
        if (memcmp(&got->rgb[i], &want->rgb[i], sizeof(float)) != 0) {
            int p = i / 3;
            printf("  %s: pixel (%d,%d) channel %d is %.9g, want %.9g\n", check_case_name,
                   p % want->width, p / want->width, i % 3, got->rgb[i], want->rgb[i]);
            return false;
        }
    }
    return true;
}

#endif
