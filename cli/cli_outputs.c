/* Output paths checked before any long work (issue 18, item 3): a file that cannot be
 * written, a picture not named .png or a folder that cannot be made is a bad command
 * line (exit 2), said at once rather than after the settling or the growing. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

/* The folder part of `path` ("." when it has none) into buf. */
static void parent_folder(const char *path, char *buf, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(buf, size, ".");
    else if (slash == path)
        snprintf(buf, size, "/");
    else
        snprintf(buf, size, "%.*s", (int)(slash - path), path);
}

static int has_extension(const char *path, const char *ext)
{
    const size_t n = strlen(path), e = strlen(ext);
    const char *slash = strrchr(path, '/');
    const size_t base = slash ? (size_t)(slash - path + 1) : 0;
    return n >= base + e + 1 && strcasecmp(path + n - e, ext) == 0;
}

int hk_cli_output_file(const char *cmd, const char *option, const char *path, const char *extension)
{
    struct stat s;
    const int exists = stat(path, &s) == 0;
    if (exists && S_ISDIR(s.st_mode)) return hk_cli_usage_error(cmd, "%s %s: is a folder, not a file", option, path);
    /* A FIFO or a device (/dev/stdout) is written in place whatever its name. */
    const int special = exists && (S_ISFIFO(s.st_mode) || S_ISCHR(s.st_mode));
    if (extension && !special && !has_extension(path, extension))
        return hk_cli_usage_error(cmd, "%s %s: the file written is a %s; give a name ending in %s", option, path,
                                  strcmp(extension, ".png") == 0 ? "PNG picture" : extension, extension);
    if (special) return 0;
    char folder[4096];
    parent_folder(path, folder, sizeof folder);
    struct stat f;
    if (stat(folder, &f) != 0 || !S_ISDIR(f.st_mode))
        return hk_cli_usage_error(cmd, "%s %s: no folder %s to write it in", option, path, folder);
    if (access(folder, W_OK | X_OK) != 0)
        return hk_cli_usage_error(cmd, "%s %s: cannot write in the folder %s (%s)", option, path, folder,
                                  strerror(errno));
    return 0;
}

/* Extensions of the files hairkit writes: a folder named like one is a mistake
 * ("simulate -o head.hair"). */
static const char *const file_extensions[] = {".hair", ".png", ".tfx", ".data", ".ply", ".obj", ".usda", ".txt"};

int hk_cli_output_folder(const char *cmd, const char *option, const char *dir)
{
    struct stat s;
    if (stat(dir, &s) == 0) {
        if (!S_ISDIR(s.st_mode))
            return hk_cli_usage_error(cmd, "%s %s: is a file, not a folder (%s writes a folder of files)", option, dir,
                                      cmd);
    } else {
        for (size_t i = 0; i < sizeof file_extensions / sizeof *file_extensions; i++)
            if (has_extension(dir, file_extensions[i]))
                return hk_cli_usage_error(cmd, "%s %s: names a %s file, but %s writes a folder of files: give a folder",
                                          option, dir, file_extensions[i], cmd);
        /* mkdir -p: every missing folder on the way. */
        char path[4096];
        if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
            return hk_cli_usage_error(cmd, "%s: the folder's name is too long", option);
        for (char *p = path + 1;; p++) {
            const char c = *p;
            if (c != '/' && c != '\0') continue;
            *p = '\0';
            if (mkdir(path, 0777) != 0 && errno != EEXIST)
                return hk_cli_usage_error(cmd, "%s %s: cannot make the folder %s (%s)", option, dir, path,
                                          strerror(errno));
            struct stat made;
            if (stat(path, &made) != 0 || !S_ISDIR(made.st_mode))
                return hk_cli_usage_error(cmd, "%s %s: %s is a file, not a folder", option, dir, path);
            *p = c;
            if (c == '\0') break;
        }
    }
    if (access(dir, W_OK | X_OK) != 0)
        return hk_cli_usage_error(cmd, "%s %s: cannot write in this folder (%s)", option, dir, strerror(errno));
    return 0;
}

int hk_cli_setup_save_file(const char *cmd, const hk_Scene *scene)
{
    if (!scene->setup.save || !scene->setup.save_file) return 0;
    char option[4200];
    snprintf(option, sizeof option, "%s: SaveFile", scene->setup_path ? scene->setup_path : "the setup");
    return hk_cli_output_file(cmd, option, scene->setup.save_file, NULL);
}
