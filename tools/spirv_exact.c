/* spirv_exact.c: decorates every float arithmetic instruction of a SPIR-V module NoContraction,
 * so that no driver fuses a multiply and an add that the C build (fp-contract off) rounds twice:
 * what `precise` did in the GLSL text, without glslang's propagation of it. Reads and writes the
 * C header that glslangValidator --vn writes (a uint32_t array of the module's words).
 * Usage: spirv_exact IN.h OUT.h */
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { DECORATE = 71, NO_CONTRACTION = 42, HEADER_WORDS = 5 };

/* Whether an instruction of opcode op may stand before the module's annotations end: the
 * preamble, debug and annotation instructions (the SPIR-V specification's logical layout). */
static bool preamble(uint32_t op) {
    static const uint32_t ops[] = {17, 10,  11, 14,  15, 16, 331, 7,  3,   4,    2,   5,
                                   6,  330, 8,  317, 71, 72, 73,  74, 332, 5632, 5633};
    for (size_t k = 0; k < sizeof ops / sizeof ops[0]; k++)
        if (ops[k] == op) return true;
    return false;
}

/* Whether opcode op is float arithmetic with a result: OpFNegate, OpFAdd, OpFSub, OpFMul,
 * OpFDiv, OpFRem, OpFMod, the vector and matrix products, OpDot, and the extended instructions
 * (length, normalize, cross, mix: a driver lowers them to multiply-adds). */
static bool float_arithmetic(uint32_t op) {
    return op == 12 || op == 127 || op == 129 || op == 131 || op == 133 ||
           (op >= 136 && op <= 148 && op != 137 && op != 138 && op != 139);
}

static bool fail(const char *what, const char *path) {
    fprintf(stderr, "spirv_exact: %s: %s\n", path, what);
    return false;
}

/* The words of the SPIR-V binary at path in *words (*count of them); false (said) on a bad file. */
static bool read_module(const char *path, uint32_t **words, size_t *count) {
    FILE *f = fopen(path, "rb");
    if (!f) return fail("cannot open", path);
    fseek(f, 0, SEEK_END);
    long bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    *words = malloc((size_t)bytes + 4);
    *count = *words ? fread(*words, 4, (size_t)bytes / 4, f) : 0;
    fclose(f);
    return *count > HEADER_WORDS || fail("no module", path);
}

/* Writes words as a C header of the uint32_t array name (what glslangValidator --vn writes). */
static bool write_header(const char *path, const char *name, const uint32_t *w, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return fail("cannot write", path);
    fprintf(f, "#pragma once\nconst uint32_t %s[] = {\n", name);
    for (size_t k = 0; k < n; k++)
        fprintf(f, "0x%08" PRIx32 "%s", w[k], k + 1 == n ? "\n};\n" : k % 8 == 7 ? ",\n" : ",");
    return fclose(f) == 0 || fail("cannot write", path);
}

int main(int argc, char **argv) {
    if (argc == 5 && !strcmp(argv[1], "--header")) { /* --header NAME IN.spv OUT.h */
        uint32_t *in;
        size_t count;
        return read_module(argv[3], &in, &count) && write_header(argv[4], argv[2], in, count) ? 0
                                                                                              : 1;
    }
    if (argc != 3) return fprintf(stderr, "usage: spirv_exact IN.spv OUT.spv\n"), 2;
    uint32_t *in;
    size_t count;
    if (!read_module(argv[1], &in, &count)) return 1;
    uint32_t bound = in[3];
    bool *decorated = calloc(bound, 1), *exact = calloc(bound, 1);
    uint32_t *out = malloc((count + 3 * (size_t)bound) * sizeof *out);
    if (!decorated || !exact || !out) return fail("out of memory", argv[1]), 1;
    size_t annotations_end = 0;
    for (size_t at = HEADER_WORDS; at < count;) {
        uint32_t op = in[at] & 0xffffu, n = in[at] >> 16;
        if (n == 0 || at + n > count) return fail("truncated instruction", argv[1]), 1;
        if (!annotations_end && !preamble(op)) annotations_end = at;
        if (op == DECORATE && n >= 3 && in[at + 2] == NO_CONTRACTION && in[at + 1] < bound)
            decorated[in[at + 1]] = true;
        if (float_arithmetic(op) && n >= 3 && in[at + 2] < bound) exact[in[at + 2]] = true;
        at += n;
    }
    if (!annotations_end) return fail("no types", argv[1]), 1;
    size_t w = 0;
    memcpy(out, in, annotations_end * sizeof *out);
    w = annotations_end;
    for (uint32_t id = 1; id < bound; id++) {
        if (!exact[id] || decorated[id]) continue;
        out[w++] = (3u << 16) | DECORATE;
        out[w++] = id;
        out[w++] = NO_CONTRACTION;
    }
    memcpy(out + w, in + annotations_end, (count - annotations_end) * sizeof *out);
    w += count - annotations_end;
    FILE *f = fopen(argv[2], "wb");
    bool ok = f && fwrite(out, 4, w, f) == w;
    ok = (f && fclose(f) == 0) && ok;
    free(in), free(out), free(decorated), free(exact);
    return ok ? 0 : (fail("cannot write", argv[2]), 1);
}
