/* The files of a simulation's folder: their names, cleaning those of an earlier run
 * (only ours: a folder may hold anything else), and the video made from the pictures. */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hairkit/simulation_file.h"
#include "sim_internal.h"

hk_Status hk_simulation_frame_path(char *buf, size_t size, const char *dir, const char *stem, long frame,
                                   const char *ext, hk_Error *err)
{
    if (snprintf(buf, size, "%s/%s_%04ld.%s", dir, stem, frame, ext) >= (int)size)
        return hk_error_set(err, HK_ERR_INVALID, "%s: output folder name too long", dir);
    return HK_OK;
}

long long hk_sim_file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long long)st.st_size : 0;
}

/* name == prefix + 4 or more digits + suffix, exactly. */
static int numbered(const char *name, const char *prefix, const char *suffix)
{
    const size_t lp = strlen(prefix), ls = strlen(suffix), n = strlen(name);
    if (n < lp + 4 + ls || strncmp(name, prefix, lp) != 0 || strcmp(name + n - ls, suffix) != 0) return 0;
    for (size_t i = lp; i < n - ls; i++)
        if (name[i] < '0' || name[i] > '9') return 0;
    return 1;
}

/* One of the names a simulation writes. */
static int ours(const char *name)
{
    return numbered(name, "frame_", ".png") || numbered(name, "frame_", ".hair") ||
           numbered(name, "guides_", ".hair") || strcmp(name, "hair.mp4") == 0 ||
           strcmp(name, HK_SIMULATION_FILE_NAME) == 0;
}

/* A temporary file hk_outfile left behind for one of our names: NAME.tmp-XXXXXX. */
static int our_temporary(const char *name)
{
    const char *t = strstr(name, ".tmp-");
    if (!t || strlen(t) != 11 || (size_t)(t - name) >= 256) return 0;
    char base[256];
    memcpy(base, name, (size_t)(t - name));
    base[t - name] = '\0';
    return ours(base);
}

hk_Status hk_simulation_clean_folder(const char *dir, int *removed, hk_Error *err)
{
    *removed = 0;
    DIR *d = opendir(dir);
    if (!d) {
        if (errno == ENOENT) return HK_OK;
        return hk_error_set(err, HK_ERR_IO, "%s: cannot read the folder: %s", dir, strerror(errno));
    }
    hk_Status st = HK_OK;
    struct dirent *e;
    while (st == HK_OK && (e = readdir(d)) != NULL) {
        if (!ours(e->d_name) && !our_temporary(e->d_name)) continue;
        char path[4096];
        struct stat s;
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path) continue;
        if (lstat(path, &s) != 0 || !S_ISREG(s.st_mode)) continue; /* not a file we wrote */
        if (unlink(path) != 0)
            st = hk_error_set(err, HK_ERR_IO, "%s: cannot remove the earlier run's file: %s", path, strerror(errno));
        else
            (*removed)++;
    }
    closedir(d);
    return st;
}

int hk_sim_make_video(const char *dir, double fps)
{
    char rate[32], pattern[4096], video[4096], tmp[4096];
    snprintf(rate, sizeof rate, "%g", fps);
    if (snprintf(pattern, sizeof pattern, "%s/frame_%%04d.png", dir) >= (int)sizeof pattern ||
        snprintf(video, sizeof video, "%s/hair.mp4", dir) >= (int)sizeof video ||
        snprintf(tmp, sizeof tmp, "%s.tmp-ffmpeg", video) >= (int)sizeof tmp)
        return -1;
    /* Run without a shell: DIR may hold anything. */
    const pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        char *const args[] = {"ffmpeg", "-y",    "-loglevel", "error",   "-framerate", rate,
                              "-i",     pattern, "-pix_fmt",  "yuv420p", "-vf",        "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                              "-f",     "mp4",   tmp,         NULL};
        execvp("ffmpeg", args);
        _exit(127); /* not installed */
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return -1;
    /* Written under a temporary name and renamed, as every output. */
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && rename(tmp, video) == 0) return 1;
    unlink(tmp);
    return WIFEXITED(status) && WEXITSTATUS(status) == 127 ? 0 : -1;
}
