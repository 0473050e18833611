/* scene_lex.c: the scene parser's lexer (parser.h): lines into tokens, tokens into numbers,
 * integers, switches and words checked against their keys' ranges, and the error and warning
 * records with file:line:col. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "scene/decimal.h"
#include "scene/parser.h"

bool parser_fail(parser *p, int col, const char *fmt, ...) {
    if (p->err) {
        snprintf(p->err->file, sizeof p->err->file, "%s", p->filename);
        p->err->line = p->line;
        p->err->col = col;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(p->err->message, sizeof p->err->message, fmt, ap);
        va_end(ap);
    }
    return false;
}

void parser_warn(parser *p, int line, int col, const char *fmt, ...) {
    if (p->s.warning_count == SCENE_MAX_WARNINGS) return;
    scene_error *w = &p->s.warnings[p->s.warning_count++];
    snprintf(w->file, sizeof w->file, "%s", p->filename);
    w->line = line;
    w->col = col;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->message, sizeof w->message, fmt, ap);
    va_end(ap);
}

/* The token as it should appear in a message; long tokens are cut so the message stays readable. */
const char *parser_quote(parser *p, const token *t) {
    char *out = p->quoted[p->quoted_next];
    p->quoted_next ^= 1;
    int n = t->length < MAX_QUOTED_CHARS ? t->length : MAX_QUOTED_CHARS;
    memcpy(out, t->text, (size_t)n);
    strcpy(out + n, t->length > n ? "..." : "");
    return out;
}

bool parser_token_is(const token *t, const char *word) {
    size_t n = strlen(word);
    return (size_t)t->length == n && memcmp(t->text, word, n) == 0;
}

/* Where a value missing at the end of the line was expected: just after the last token. */
int parser_end_col(const parser *p) {
    const token *last = &p->tokens[p->token_count - 1];
    return last->col + last->length;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

/* [+-]?(digits[.digits*]|.digits)([eE][+-]?digits)? and nothing else: no nan, inf or hex. */
static bool is_decimal(const char *s, int n) {
    int i = 0, digits = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    for (; i < n && is_digit(s[i]); i++) digits++;
    if (i < n && s[i] == '.') {
        for (i++; i < n && is_digit(s[i]); i++) digits++;
    }
    if (digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        int exponent_digits = 0;
        for (; i < n && is_digit(s[i]); i++) exponent_digits++;
        if (exponent_digits == 0) return false;
    }
    return i == n;
}

/* Case-insensitive match of the words strtod would take for NaN or an infinity. */
static bool is_nonfinite_word(const token *t) {
    const char *s = t->text;
    int n = t->length;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) {
        s++;
        n--;
    }
    static const char *const words[] = {"nan", "inf", "infinity"};
    for (size_t w = 0; w < sizeof words / sizeof words[0]; w++) {
        if ((size_t)n == strlen(words[w]) && strncasecmp(s, words[w], (size_t)n) == 0) return true;
    }
    return false;
}

/* The largest |coordinate| of v, at least 1: what the ray offset TZ_EPS is scaled by there. */
float parser_largest_coordinate(vec3 v) { return fmaxf(v3_max_abs(v), 1.0f); }

static bool fail_range(parser *p, const key_spec *k, const token *t) {
    if (k->kind == VALUE_INTEGER) {
        return parser_fail(p, t->col, "%s must be an integer in [%.0f, %.0f], got %s", k->name,
                           k->min, k->max, parser_quote(p, t));
    }
    if (k->min_exclusive) {
        return parser_fail(p, t->col, "%s must be in (%g, %g], got %s", k->name, k->min, k->max,
                           parser_quote(p, t));
    }
    if (k->max < FLT_MAX) {
        return parser_fail(p, t->col, "%s must be in [%g, %g], got %s", k->name, k->min, k->max,
                           parser_quote(p, t));
    }
    return parser_fail(p, t->col, "%s must be >= %g, got %s", k->name, k->min, parser_quote(p, t));
}

static bool parse_number(parser *p, const key_spec *k, const token *t, double *out) {
    if (!is_decimal(t->text, t->length)) {
        const char *why = "";
        if (is_nonfinite_word(t)) why = " (NaN and infinities are not allowed)";
        if (t->length > 2 && t->text[0] == '0' && (t->text[1] == 'x' || t->text[1] == 'X')) {
            why = " (hexadecimal numbers are not allowed)";
        }
        return parser_fail(p, t->col, "expected a number for '%s', got '%s'%s", k->name,
                           parser_quote(p, t), why);
    }
    double d;
    if (!decimal_fast(t->text, t->length, &d)) {
        memcpy(p->number, t->text, (size_t)t->length);
        p->number[t->length] = '\0';
        d = strtod(p->number, NULL);
    }
    if (!(fabs(d) <= FLT_MAX)) {
        return parser_fail(p, t->col, "number '%s' for '%s' is out of range (magnitude above %g)",
                           parser_quote(p, t), k->name, FLT_MAX);
    }
    /* Check the float the renderer will see, so 1e-50 is a zero radius, not a tiny one. */
    float f = (float)d;
    float min = (float)k->min, max = (float)k->max; /* as written: "1e-12" is in [1e-12, ..] */
    if (f < min || f > max || (k->min_exclusive && f == min)) return fail_range(p, k, t);
    *out = f;
    return true;
}

static bool parse_integer(parser *p, const key_spec *k, const token *t, double *out) {
    const char *s = t->text;
    int n = t->length, i = 0;
    bool negative = false;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) negative = s[i++] == '-';
    if (i == n) {
        return parser_fail(p, t->col, "expected an integer for '%s', got '%s'", k->name,
                           parser_quote(p, t));
    }
    /* Saturating: anything past 10^12 is out of every integer range. */
    double value = 0.0;
    for (; i < n; i++) {
        if (!is_digit(s[i])) {
            return parser_fail(p, t->col, "expected an integer for '%s', got '%s'", k->name,
                               parser_quote(p, t));
        }
        if (value < 1e12) value = value * 10.0 + (s[i] - '0');
    }
    if (negative) value = -value;
    if (value < k->min || value > k->max) return fail_range(p, k, t);
    *out = value;
    return true;
}

static bool parse_switch(parser *p, const key_spec *k, const token *t, double *out) {
    if (parser_token_is(t, "on") || parser_token_is(t, "off")) {
        *out = parser_token_is(t, "on");
        return true;
    }
    return parser_fail(p, t->col, "expected on or off for '%s', got '%s'", k->name,
                       parser_quote(p, t));
}

/* One of the space-separated words of k->components; the value is its index. */
static bool parse_word(parser *p, const key_spec *k, const token *t, double *out) {
    const char *w = k->components;
    for (int index = 0; *w; index++) {
        size_t n = strcspn(w, " ");
        if ((size_t)t->length == n && memcmp(t->text, w, n) == 0) {
            *out = index;
            return true;
        }
        w += n + (w[n] == ' ');
    }
    return parser_fail(p, t->col, "expected one of %s for '%s', got '%s'", k->components, k->name,
                       parser_quote(p, t));
}

/* Parses the value(s) of key k from token *next on; advances *next past them. */
bool parser_values(parser *p, const key_spec *k, int *next, double value[3], int value_token[3]) {
    int count = 1;
    if (k->components && k->kind != VALUE_WORD) /* "x y z" three numbers, "u v" two */
        count = 1 + (strchr(k->components, ' ') != NULL) +
                (strchr(k->components, ' ') != strrchr(k->components, ' '));
    for (int c = 0; c < count; c++) {
        if (*next >= p->token_count) {
            if (count == 1) {
                return parser_fail(p, parser_end_col(p),
                                   "expected a value for '%s', got end of line", k->name);
            }
            return parser_fail(p, parser_end_col(p), "expected %d numbers (%s) for '%s', got %d",
                               count, k->components, k->name, c);
        }
        value_token[c] = *next;
        const token *t = &p->tokens[(*next)++];
        bool ok = k->kind == VALUE_NUMBER    ? parse_number(p, k, t, &value[c])
                  : k->kind == VALUE_INTEGER ? parse_integer(p, k, t, &value[c])
                  : k->kind == VALUE_SWITCH  ? parse_switch(p, k, t, &value[c])
                  : k->kind == VALUE_PATH    ? (value[c] = 0.0, true)
                                             : parse_word(p, k, t, &value[c]);
        if (!ok) return false;
    }
    return true;
}

/* Parses `key value...` pairs from token `first` to the end of the line into *kv.
 * `accepted` masks which keys of `keys` this directive (or material) takes; messages name the
 * owner, followed by word unless it is NULL (formatted only for a message: spheres are many). */
bool parser_keys_of(parser *p, const char *owner, const char *word, const key_spec *keys,
                    int key_count, unsigned accepted, int first, key_values *kv) {
    memset(kv, 0, sizeof *kv);
    int next = first;
    while (next < p->token_count) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < key_count && !((accepted & BIT(key)) && parser_token_is(t, keys[key].name)))
            key++;
        if (key == key_count) {
            char list[512] = "";
            for (int k = 0; k < key_count; k++) {
                if (!(accepted & BIT(k))) continue;
                if (!strcmp(keys[k].name, "color_map")) { /* the material's texture keys, last */
                    strcat(list, " and the texture keys");
                    break;
                }
                if (list[0]) strcat(list, " ");
                strcat(list, keys[k].name);
            }
            return parser_fail(p, t->col, "unknown key '%s' for %s%s%s (expected one of: %s)",
                               parser_quote(p, t), owner, word ? " " : "", word ? word : "", list);
        }
        if (kv->given & BIT(key)) return parser_fail(p, t->col, "'%s' given twice", keys[key].name);
        kv->given |= BIT(key);
        kv->key_token[key] = next - 1;
        if (!parser_values(p, &keys[key], &next, kv->value[key], kv->value_token[key])) {
            return false;
        }
    }
    return true;
}

bool parser_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                 unsigned accepted, int first, key_values *kv) {
    return parser_keys_of(p, owner, NULL, keys, key_count, accepted, first, kv);
}

/* Checks that every key in `required` was given; the error points at the directive word. */
bool parser_require_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                         unsigned required, const key_values *kv) {
    for (int k = 0; k < key_count; k++) {
        if ((required & BIT(k)) && !(kv->given & BIT(k))) {
            return parser_fail(p, p->tokens[0].col, "%s is missing required key '%s'", owner,
                               keys[k].name);
        }
    }
    return true;
}

vec3 parser_vec3(const key_values *kv, int key, vec3 fallback) {
    if (!(kv->given & BIT(key))) return fallback;
    return v3((float)kv->value[key][0], (float)kv->value[key][1], (float)kv->value[key][2]);
}

double parser_value_or(const key_values *kv, int key, double fallback) {
    return (kv->given & BIT(key)) ? kv->value[key][0] : fallback;
}

/* Fails at byte i of the line, which cannot be scene text: a NUL, a UTF-8 byte-order mark, or
 * another byte that is not printable ASCII (said apart: each has its own likely cause). */
static bool fail_byte(parser *p, const char *line, size_t length, size_t i) {
    unsigned char c = (unsigned char)line[i];
    int col = (int)i + 1;
    if (c == 0) return parser_fail(p, col, "unexpected NUL byte (is this a text file?)");
    if (p->line == 1 && i == 0 && length >= 3 && !memcmp(line, "\xef\xbb\xbf", 3))
        return parser_fail(p, col,
                           "a UTF-8 byte-order mark (EF BB BF) starts the file: save it without "
                           "one");
    return parser_fail(p, col, "unexpected byte 0x%02x (only printable ASCII outside comments)", c);
}

/* The end of the quoted token opened at line[start] (a '"'): the index of its closing quote.
 * Inside, printable ASCII and spaces, '#' too, with \" and \\ the only escapes; a closing quote
 * is followed by a space, a comment or the line's end. False (reported) otherwise. */
static bool quoted_end(parser *p, const char *line, size_t length, size_t start, size_t *end) {
    size_t i = start + 1;
    for (; i < length && line[i] != '"'; i++) {
        unsigned char c = (unsigned char)line[i];
        if (c == '\\') {
            if (i + 1 < length && (line[i + 1] == '"' || line[i + 1] == '\\')) {
                i++;
                continue;
            }
            return parser_fail(p, (int)i + 1,
                               "unknown escape in a quoted path: only \\\" (a quote) and \\\\ (a "
                               "backslash) are escapes");
        }
        if (c == '\r' && i == length - 1) break; /* the CR of a CR LF ending */
        if (c < 0x20 || c > 0x7e) return fail_byte(p, line, length, i);
    }
    if (i >= length || line[i] != '"')
        return parser_fail(p, (int)start + 1,
                           "unterminated quoted path: the '\"' here has no closing '\"' on its "
                           "line");
    if (i + 1 < length && !strchr(" \t\r#", line[i + 1]))
        return parser_fail(p, (int)i + 2, "expected a space after the closing quote");
    *end = i;
    return true;
}

/* Splits one line (without its '\n') into p->tokens, rejecting bytes that cannot be scene text.
 * Outside comments only printable ASCII, tab and a CR ending the line (whitespace) are allowed;
 * inside a comment anything but NUL, so comments may hold UTF-8. A token that starts with '"'
 * runs to its closing quote (a path with spaces: parser_path). */
bool parser_tokenize(parser *p, const char *line, size_t length) {
    p->token_count = 0;
    /* Only the last byte may be a CR (CR LF endings), comments included. */
    const char *cr = length > 1 ? memchr(line, '\r', length - 1) : NULL;
    if (cr) {
        return parser_fail(p, (int)(cr - line) + 1,
                           "carriage return inside a line (old Mac line endings?): lines end "
                           "in LF or CR LF");
    }
    for (size_t i = 0; i < length;) {
        unsigned char c = (unsigned char)line[i];
        int col = (int)i + 1;
        if (c == '#') {
            const char *nul = memchr(line + i, '\0', length - i);
            if (nul) return parser_fail(p, (int)(nul - line) + 1, "NUL byte in a comment");
            break;
        }
        if (c == ' ' || c == '\t' || c == '\r') {
            i++;
            continue;
        }
        if (c < 0x20 || c > 0x7e) return fail_byte(p, line, length, i);
        size_t start = i;
        if (c == '"') {
            if (!quoted_end(p, line, length, start, &i)) return false;
            i++;
        } else {
            while (i < length && line[i] > 0x20 && line[i] < 0x7f && line[i] != '#' &&
                   line[i] != '"')
                i++;
            if (i < length && line[i] == '"')
                return parser_fail(p, (int)i + 1,
                                   "a quote inside a word: a quoted path starts after a space");
        }
        p->tokens[p->token_count++] = (token){line + start, (int)(i - start), col};
    }
    return true;
}

/* A quoted token's path is its text between the quotes, \" and \\ read as the one character they
 * escape (the tokenizer took no other escape). */
bool parser_path(parser *p, const token *t, char *out, size_t size) {
    bool quoted = t->text[0] == '"';
    int from = quoted ? 1 : 0, to = quoted ? t->length - 1 : t->length;
    size_t n = 0;
    for (int i = from; i < to; i++) {
        if (quoted && t->text[i] == '\\') i++;
        if (n + 1 >= size) return parser_fail(p, t->col, "path is too long");
        out[n++] = t->text[i];
    }
    out[n] = '\0';
    if (n == 0) return parser_fail(p, t->col, "expected a path, got an empty one");
    return true;
}
