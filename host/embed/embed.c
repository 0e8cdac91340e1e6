/* Build tool: turns a file into a C array so that lvcl carries its kernels
 * and default scenes inside the executable.
 *
 *   embed source NAME FILE   OpenCL source with its #include "..." files
 *                            inlined (each file once), for clCreateProgramWithSource
 *   embed bytes NAME FILE    the file as it is
 *
 * Writes to stdout: const unsigned char NAME[] (NUL-terminated) and
 * const size_t NAME_size (without the NUL). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILES 256

static char seen[MAX_FILES][1024];
static int seen_count;
static size_t written;

static void emit_byte(int c)
{
    printf("%s0x%02x", written % 16 ? "," : (written ? ",\n" : ""), c & 0xff);
    written++;
}

static void emit_text(const char *s)
{
    for (; *s; s++) emit_byte(*s);
}

/* Folds "dir/../" out of a path, so that a file reached through
 * different relative includes is recognised as the same file. */
static void normalize(char *path)
{
    char *up;
    while ((up = strstr(path, "/../"))) {
        char *start = up;
        while (start > path && start[-1] != '/') start--;
        if (start == up || !strncmp(start, "../", 3)) break; /* nothing to fold: a leading ".." */
        memmove(start, up + 4, strlen(up + 4) + 1);
    }
}

static int already_seen(const char *path)
{
    for (int i = 0; i < seen_count; i++)
        if (!strcmp(seen[i], path)) return 1;
    if (seen_count == MAX_FILES) {
        fprintf(stderr, "embed: more than %d included files\n", MAX_FILES);
        exit(1);
    }
    snprintf(seen[seen_count++], sizeof seen[0], "%s", path);
    return 0;
}

static void emit_source(const char *path)
{
    if (already_seen(path)) return;
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "embed: cannot open %s\n", path);
        exit(1);
    }
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) slash[1] = 0;
    else dir[0] = 0;

    char line[4096];
    while (fgets(line, sizeof line, f)) {
        char name[512];
        if (sscanf(line, " #include \"%511[^\"]\"", name) == 1) {
            char inc[1024 + 512];
            snprintf(inc, sizeof inc, "%s%s", dir, name);
            normalize(inc);
            emit_source(inc);
        } else {
            emit_text(line);
        }
    }
    fclose(f);
}

static void emit_bytes(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "embed: cannot open %s\n", path);
        exit(1);
    }
    int c;
    while ((c = fgetc(f)) != EOF) emit_byte(c);
    fclose(f);
}

int main(int argc, char **argv)
{
    if (argc != 4 || (strcmp(argv[1], "source") && strcmp(argv[1], "bytes"))) {
        fprintf(stderr, "usage: embed source|bytes NAME FILE\n");
        return 2;
    }
    printf("#include <stddef.h>\nconst unsigned char %s[] = {\n", argv[2]);
    if (!strcmp(argv[1], "source")) emit_source(argv[3]);
    else emit_bytes(argv[3]);
    size_t size = written;
    emit_byte(0);
    printf("};\nconst size_t %s_size = %zu;\n", argv[2], size);
    return 0;
}
