/* The glTF specification's corner cases (tests/data/gltf/corners, written
 * by make_corners.py with cases.txt): every quad_* file must import to the
 * same unit square, facing +Z, with its normals and UVs; every bad_* file
 * must be refused with one line naming the file and the problem.
 * Usage: test_gltf_corners TESTS_DIR. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/scene/scene.h"
#include "../check.h"
#include "capture.h"

static char corners_dir[4096];

typedef struct {
    float p[3][3];
} triangle;

static int near(float a, float b)
{
    return fabsf(a - b) < 1e-4f;
}

static int less3(const float *a, const float *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k];
    return 0;
}

/* Rotates the corners so the smallest comes first: the winding is kept,
 * and two listings of one triangle compare equal. */
static triangle canonical(triangle t)
{
    int first = 0;
    for (int c = 1; c < 3; c++)
        if (less3(t.p[c], t.p[first])) first = c;
    triangle r;
    for (int c = 0; c < 3; c++) memcpy(r.p[c], t.p[(first + c) % 3], sizeof r.p[c]);
    return r;
}

static int same_triangle(const triangle *a, const triangle *b)
{
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++)
            if (!near(a->p[c][k], b->p[c][k])) return 0;
    return 1;
}

/* Whether the flattened scene is the square (0,1,2) + (0,2,3), in any
 * triangle order, with unit +Z normals and UVs equal to x, y where the
 * triangles carry them; `why` says what differs. */
static int is_square(const lvcl_scene *s, char *why, size_t n)
{
    static const float sq[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    triangle want[2];
    static const int list[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++) memcpy(want[i / 3].p[i % 3], sq[list[i]], sizeof sq[0]);
    if (s->triangle_count != 2) {
        snprintf(why, n, "%zu triangles, not 2", s->triangle_count);
        return 0;
    }
    int matched[2] = {0, 0};
    for (size_t t = 0; t < 2; t++) {
        triangle got;
        for (int c = 0; c < 3; c++) memcpy(got.p[c], &s->positions[3 * s->indices[3 * t + (size_t)c]], sizeof got.p[c]);
        got = canonical(got);
        int found = 0;
        for (int w = 0; w < 2; w++)
            if (!matched[w] && same_triangle(&got, &want[w])) matched[w] = found = 1;
        if (!found) {
            snprintf(why, n, "triangle %zu (%g %g %g) (%g %g %g) (%g %g %g) is not half of the square", t, got.p[0][0],
                     got.p[0][1], got.p[0][2], got.p[1][0], got.p[1][1], got.p[1][2], got.p[2][0], got.p[2][1],
                     got.p[2][2]);
            return 0;
        }
        for (int c = 0; c < 3; c++) {
            uint32_t v = s->indices[3 * t + (size_t)c];
            const float *p = &s->positions[3 * v], *nrm = &s->normals[3 * v], *uv = &s->uvs[2 * v];
            if ((s->tri_flags[t] & LV_TRI_HAS_NORMALS) && !(near(nrm[0], 0) && near(nrm[1], 0) && near(nrm[2], 1))) {
                snprintf(why, n, "vertex %u: normal (%g %g %g), not +Z", v, nrm[0], nrm[1], nrm[2]);
                return 0;
            }
            if ((s->tri_flags[t] & LV_TRI_HAS_UVS) && !(near(uv[0], p[0]) && near(uv[1], p[1]))) {
                snprintf(why, n, "vertex %u at (%g %g): uv (%g %g)", v, p[0], p[1], uv[0], uv[1]);
                return 0;
            }
        }
    }
    return 1;
}

/* What cases.txt asks of one file. */
typedef struct {
    char file[256];
    int ok;             /* must load (else must fail with `code`) */
    lvcl_error code;    /* the error it must give */
    char fragment[256]; /* in the warning (ok) or the error message */
} expectation;

static int parse_code(const char *word, lvcl_error *code)
{
    static const struct {
        const char *name;
        lvcl_error code;
    } names[] = {{"io", LVCL_ERR_IO}, {"parse", LVCL_ERR_PARSE}, {"unsupported", LVCL_ERR_UNSUPPORTED}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(word, names[i].name) == 0) return *code = names[i].code, 1;
    return 0;
}

/* One line of cases.txt: FILE ok [warning=TEXT] | FILE CODE TEXT. */
static int parse_case(char *line, expectation *e)
{
    memset(e, 0, sizeof *e);
    line[strcspn(line, "\n")] = '\0';
    char *file = strtok(line, " "), *kind = strtok(NULL, " "), *rest = strtok(NULL, "");
    if (!file || !kind || strlen(file) >= sizeof e->file) return 0;
    snprintf(e->file, sizeof e->file, "%s", file);
    if (strcmp(kind, "ok") == 0) {
        e->ok = 1;
        if (rest && strncmp(rest, "warning=", 8) == 0) snprintf(e->fragment, sizeof e->fragment, "%s", rest + 8);
        return 1;
    }
    if (!parse_code(kind, &e->code) || !rest) return 0;
    snprintf(e->fragment, sizeof e->fragment, "%s", rest);
    return 1;
}

static void check_case(const expectation *e)
{
    char path[4608], name[512], why[256] = "";
    snprintf(path, sizeof path, "%s/%s", corners_dir, e->file);
    lvcl_scene s;
    lvcl_status st = {0};
    capture cap;
    capture_begin(&cap);
    lvcl_error got = lvcl_scene_load_gltf_file(path, &s, &st);
    if (got == LVCL_OK) got = lvcl_scene_flatten(&s, &st);
    char *warnings = capture_end(&cap);

    if (e->ok) {
        snprintf(name, sizeof name, "%s: imports as the unit square", e->file);
        CHECK(name, got == LVCL_OK && is_square(&s, why, sizeof why), "%s", got == LVCL_OK ? why : st.message);
        if (e->fragment[0] && !verbose()) {
            snprintf(name, sizeof name, "%s: warns \"%s\"", e->file, e->fragment);
            CHECK(name, warnings && strstr(warnings, e->fragment), "stderr: %s", warnings ? warnings : "");
        }
    } else {
        snprintf(name, sizeof name, "%s: refused in one line", e->file);
        CHECK(name,
              got == e->code && strstr(st.message, e->file) && strstr(st.message, e->fragment) &&
                  !strchr(st.message, '\n'),
              "error %d (want %d, with \"%s\"): %s", got, e->code, e->fragment, st.message);
        if (got != LVCL_OK) printf("  message: %s\n", st.message);
    }
    snprintf(name, sizeof name, "%s: no sanitizer report", e->file);
    if (sanitizer_report(warnings)) CHECK(name, 0, "%s", warnings);
    free(warnings);
    if (got == LVCL_OK) {
        if (strcmp(e->file, "quad_camera_without_aspect.gltf") == 0) {
            const lvcl_camera_desc *c = &s.camera;
            CHECK("camera without aspectRatio: kept, the image's aspect used",
                  c->present && c->aspect == 0.0f && near(c->yfov, 0.7f) && near(c->position[2], 3.0f),
                  "present %d aspect %g yfov %g", c->present, c->aspect, c->yfov);
        }
        lvcl_scene_free(&s);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_DIR\n", argv[0]);
        return 2;
    }
    snprintf(corners_dir, sizeof corners_dir, "%s/data/gltf/corners", argv[1]);
    char list[4200];
    snprintf(list, sizeof list, "%s/cases.txt", corners_dir);
    FILE *f = fopen(list, "r");
    CHECK("cases.txt readable", f != NULL, "cannot open %s", list);
    if (!f) CHECK_EXIT();
    char line[1024];
    int cases = 0, ok = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n') continue;
        expectation e;
        if (!parse_case(line, &e)) {
            CHECK("cases.txt line parses", 0, "%s", line);
            continue;
        }
        check_case(&e);
        cases++;
        ok += e.ok;
    }
    fclose(f);
    printf("  %d cases: %d must load, %d must be refused\n", cases, ok, cases - ok);
    CHECK_EXIT();
}
