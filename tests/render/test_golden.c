/* Behaviour pins: exact hashes of small renders (pt, lv with either gather,
 * lv-all) of the Cornell box, the glass table and the kitchen at fixed
 * seeds, and of a room holding every BSDF family and light kind
 * (tests/data/golden/make_materials.py). A refactoring must leave every
 * pixel bit for bit as it was.
 *
 * The hashes depend on the OpenCL device and driver (a different CPU may
 * round some built-ins differently), so tests/data/golden.txt keeps them per
 * device. On a device with no entry the checks are skipped, saying so, and
 * so is a case with no entry on a device that has others;
 *   build/tests/test_golden tests --record
 * renders the cases and writes this device's entries (replacing its old ones). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"

typedef struct {
    const char *scene; /* embedded name, or a path relative to the tests folder */
    const char *mode;  /* pt, lv (integrating gather), lv-sample, lv-all */
} golden_case;

static const golden_case cases[] = {
    {"cornell", "pt"},
    {"cornell", "lv"},
    {"cornell", "lv-sample"},
    {"cornell", "lv-all"},
    {"../scenes/glass-table.gltf", "pt"},
    {"../scenes/glass-table.gltf", "lv"},
    {"../scenes/glass-table.gltf", "lv-sample"},
    {"../scenes/glass-table.gltf", "lv-all"},
    {"kitchen", "pt"},
    {"kitchen", "lv"},
    {"kitchen", "lv-sample"},
    {"kitchen", "lv-all"},
    /* every BSDF family, textures, shading normals, a mirrored instance, point and spot lights */
    {"data/golden/materials.gltf", "pt"},
    {"data/golden/materials.gltf", "lv"},
    {"data/golden/materials.gltf", "lv-sample"},
    {"data/golden/materials.gltf", "lv-all"},
};
#define CASE_COUNT (sizeof cases / sizeof cases[0])

/* FNV-1a over the image's float bits. */
static uint64_t hash_image(const float *rgb, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ull;
    const unsigned char *b = (const unsigned char *)rgb;
    for (size_t i = 0; i < n * sizeof(float); i++) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

static int render_case(const char *tests_dir, const golden_case *c, uint64_t *hash, double *sum, char *why,
                       size_t why_size)
{
    char path[1024];
    const char *name = c->scene;
    if (strchr(c->scene, '/')) {
        snprintf(path, sizeof path, "%s/%s", tests_dir, c->scene);
        name = path;
    }
    lvcl_status st = {0};
    lvcl_scene scene;
    if (lvcl_scene_load(name, &scene, &st)) {
        snprintf(why, why_size, "cannot load: %s", st.message);
        return 0;
    }
    int lv = strcmp(c->mode, "pt") != 0;
    lvcl_mode mode = !lv ? LVCL_MODE_PT : !strcmp(c->mode, "lv-all") ? LVCL_MODE_LV_ALL : LVCL_MODE_LV;
    lvcl_render_request req = harness_request(mode, 24, 2, 16, 20000);
    req.integrate = strcmp(c->mode, "lv-sample") != 0;
    lvcl_render_result r;
    if (harness_render(&scene, NULL, 7, &req, &r, &st)) {
        snprintf(why, why_size, "render failed: %s", st.message);
        return 0;
    }
    size_t n = (size_t)r.width * r.height * 3;
    *hash = hash_image(r.rgb, n);
    *sum = 0;
    for (size_t i = 0; i < n; i++) *sum += r.rgb[i];
    free(r.rgb);
    return 1;
}

/* The key the hashes are kept under: device, platform and driver. */
static void device_key(char *key, size_t size)
{
    lvcl_device dev;
    lvcl_status st = {0};
    lvcl_device_prepare_environment();
    if (lvcl_device_open(getenv("LVCL_TEST_DEVICE"), &dev, &st)) {
        printf("FAIL golden: cannot open the device: %s\n", st.message);
        exit(1);
    }
    snprintf(key, size, "%s | %s | %s", dev.name, dev.platform_name, dev.driver_version);
    lvcl_device_close(&dev);
}

/* Looks up case `c`'s recorded hash for `key` in the golden file. */
static int recorded(FILE *f, const char *key, const golden_case *c, uint64_t *hash)
{
    char line[2048];
    rewind(f);
    while (fgets(line, sizeof line, f)) {
        char *k = strtok(line, "\t"), *scene = strtok(NULL, "\t"), *mode = strtok(NULL, "\t"),
             *h = strtok(NULL, "\t\n");
        if (k && scene && mode && h && !strcmp(k, key) && !strcmp(scene, c->scene) && !strcmp(mode, c->mode)) {
            *hash = strtoull(h, NULL, 16);
            return 1;
        }
    }
    return 0;
}

/* Rewrites the golden file with this device's entries replaced. */
static int record(const char *file, const char *key, const char *tests_dir)
{
    FILE *in = fopen(file, "r");
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.new", file);
    FILE *out = fopen(tmp, "w");
    if (!out) {
        printf("FAIL golden record: cannot write %s\n", tmp);
        return 1;
    }
    char line[2048];
    while (in && fgets(line, sizeof line, in)) {
        size_t kl = strlen(key);
        if (line[0] == '#' || strncmp(line, key, kl) || line[kl] != '\t') fputs(line, out);
    }
    if (in) fclose(in);
    else fputs("# device | platform | driver<TAB>scene<TAB>mode<TAB>FNV-1a of the image's floats<TAB>pixel sum\n", out);
    for (size_t i = 0; i < CASE_COUNT; i++) {
        uint64_t h;
        double sum;
        char why[600];
        if (!render_case(tests_dir, &cases[i], &h, &sum, why, sizeof why)) {
            printf("FAIL golden record %s %s: %s\n", cases[i].scene, cases[i].mode, why);
            fclose(out);
            return 1;
        }
        fprintf(out, "%s\t%s\t%s\t%016llx\t%.9g\n", key, cases[i].scene, cases[i].mode, (unsigned long long)h, sum);
        printf("recorded %s %s %016llx\n", cases[i].scene, cases[i].mode, (unsigned long long)h);
    }
    fclose(out);
    return rename(tmp, file) ? 1 : 0;
}

int main(int argc, char **argv)
{
    const char *tests_dir = argc > 1 ? argv[1] : "tests";
    char file[1024], key[800];
    snprintf(file, sizeof file, "%s/data/golden.txt", tests_dir);
    device_key(key, sizeof key);
    if (argc > 2 && !strcmp(argv[2], "--record")) return record(file, key, tests_dir);

    FILE *f = fopen(file, "r");
    uint64_t probe;
    if (!f || !recorded(f, key, &cases[0], &probe)) {
        char why[1200];
        snprintf(why, sizeof why,
                 "no hashes recorded for '%s' in %s (record them with: build/tests/test_golden %s --record)", key, file,
                 tests_dir);
        SKIP("golden images", why);
        if (f) fclose(f);
        return 0;
    }
    for (size_t i = 0; i < CASE_COUNT; i++) {
        char name[200], why[600];
        snprintf(name, sizeof name, "golden %s %s", cases[i].scene, cases[i].mode);
        uint64_t want, got;
        double sum;
        if (!recorded(f, key, &cases[i], &want)) {
            /* A case whose pixels a change moved on purpose, where only
             * some devices could record it again. */
            SKIP(name, "no hash recorded for this case on this device (record them with --record)");
            continue;
        }
        if (!render_case(tests_dir, &cases[i], &got, &sum, why, sizeof why)) {
            CHECK(name, 0, "%s", why);
            continue;
        }
        CHECK(name, got == want, "image hash %016llx (pixel sum %.9g), recorded %016llx", (unsigned long long)got, sum,
              (unsigned long long)want);
    }
    fclose(f);
    CHECK_EXIT();
}
