/* Atomic output files: temporary name in the same folder, then rename (see outfile.h);
 * symbolic links followed, FIFOs and character devices written in place, and the live
 * temporaries removed when the process is killed by SIGINT, SIGTERM, SIGHUP or SIGPIPE. */
#include "io/outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- Temporaries a signal handler may remove --------------------------------------
 * A fixed table, so that the handler touches no allocator and no lock: a slot is
 * claimed (0 -> 1), its path copied, then made live (2); the handler unlinks the live
 * ones. A temporary whose path is too long, or found the table full, is still removed
 * on every error; only a signal would leave it. */
#define SLOTS     16
#define SLOT_PATH 4096
static char slot_path[SLOTS][SLOT_PATH];
static atomic_int slot_state[SLOTS];

static void slot_register(const char *tmp)
{
    if (strlen(tmp) >= SLOT_PATH) return;
    for (int i = 0; i < SLOTS; i++) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&slot_state[i], &expected, 1)) {
            strcpy(slot_path[i], tmp);
            atomic_store(&slot_state[i], 2);
            return;
        }
    }
}

static void slot_release(const char *tmp)
{
    for (int i = 0; i < SLOTS; i++)
        if (atomic_load(&slot_state[i]) == 2 && strcmp(slot_path[i], tmp) == 0) {
            atomic_store(&slot_state[i], 0);
            return;
        }
}

/* A free name "<path>.tmp-" + 6 characters (tmp holds the path and 6 more, from
 * stem), registered for the signal handler *before* the file is made with O_EXCL: a
 * signal in between finds a name without a file (its unlink fails, harmlessly). With
 * mkstemp the file came first and the registration after it, and a SIGTERM in between
 * left the temporary behind (seen once in tests/cli/outputs.sh: guides_0003.hair.tmp-*
 * after a stopped simulate). Returns the open descriptor, or -1 with errno. */
static int create_registered(char *tmp, size_t stem)
{
    static atomic_uint counter;
    static const char symbols[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    for (unsigned attempt = 0; attempt < 100; attempt++) {
        /* 36^6 > 2^31 names; O_EXCL settles a collision with a retry */
        unsigned x = (unsigned)getpid() * 2654435761u ^ (unsigned)now.tv_nsec ^
                     (atomic_fetch_add(&counter, 1u) + attempt) * 2246822519u;
        for (int i = 0; i < 6; i++, x /= 36u) tmp[stem + (size_t)i] = symbols[x % 36u];
        slot_register(tmp);
        const int fd = open(tmp, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd >= 0) return fd;
        const int e = errno;
        slot_release(tmp);
        if (e != EEXIST) {
            errno = e;
            return -1;
        }
    }
    errno = EEXIST;
    return -1;
}

/* Only async-signal-safe calls: unlink, signal, raise. The signal is blocked while the
 * handler runs, so raise() leaves it pending and the default action (the end of the
 * process, as without the handler) follows the return. */
static void remove_temporaries(int sig)
{
    const int saved = errno;
    for (int i = 0; i < SLOTS; i++)
        if (atomic_load(&slot_state[i]) == 2) unlink(slot_path[i]);
    signal(sig, SIG_DFL);
    raise(sig);
    errno = saved;
}

void hk_outfile_cleanup_on_signals(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++) {
        struct sigaction old;
        /* A signal the program ignores (nohup, a background job's SIGINT) or handles
         * itself is left alone. */
        if (sigaction(sigs[i], NULL, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = remove_temporaries;
        sigemptyset(&sa.sa_mask);
        for (size_t j = 0; j < sizeof sigs / sizeof *sigs; j++) sigaddset(&sa.sa_mask, sigs[j]);
        sigaction(sigs[i], &sa, NULL);
    }
}

/* ---- Output files ------------------------------------------------------------------ */

static char *dup_string(const char *s, size_t extra, hk_Error *err)
{
    size_t n = strlen(s);
    char *d = hk_alloc_array(n + extra + 1, 1, err);
    if (d) memcpy(d, s, n + 1);
    return d;
}

/* The file a chain of symbolic links ends at (which may not exist yet: a dangling link
 * names the file to create), so that the temporary is made next to it and renamed over
 * it rather than over the link. path itself when it is not a link. */
static char *follow_links(const char *path, hk_Error *err)
{
    char *cur = dup_string(path, 0, err);
    for (int hops = 0; cur; hops++) {
        struct stat sb;
        if (lstat(cur, &sb) != 0 || !S_ISLNK(sb.st_mode)) return cur;
        if (hops == 40) {
            hk_error_set(err, HK_ERR_IO, "%s: too many levels of symbolic links", path);
            break;
        }
        char target[4096];
        const ssize_t n = readlink(cur, target, sizeof target - 1);
        if (n < 0 || n == (ssize_t)sizeof target - 1) {
            hk_error_set(err, HK_ERR_IO, "%s: cannot read the symbolic link %s: %s", path, cur,
                         n < 0 ? strerror(errno) : "target too long");
            break;
        }
        target[n] = '\0';
        /* A relative target is relative to the link's folder. */
        const char *slash = strrchr(cur, '/');
        const size_t dir = target[0] == '/' || !slash ? 0 : (size_t)(slash - cur) + 1;
        char *next = hk_alloc_array(dir + (size_t)n + 1, 1, err);
        if (!next) break;
        memcpy(next, cur, dir);
        memcpy(next + dir, target, (size_t)n + 1);
        free(cur);
        cur = next;
    }
    free(cur);
    return NULL;
}

/* An existing output that is not a regular file: a FIFO or a character device
 * (/dev/null, /dev/stdout on a pipe or a terminal) is written in place, without a
 * temporary; anything else (a folder, a block device, a socket) is refused. */
static hk_Status open_in_place(hk_OutFile *out, const char *path, const struct stat *sb, hk_Error *err)
{
    if (S_ISDIR(sb->st_mode)) return hk_error_set(err, HK_ERR_IO, "%s: is a folder, not a file", path);
    if (!S_ISFIFO(sb->st_mode) && !S_ISCHR(sb->st_mode))
        return hk_error_set(err, HK_ERR_IO,
                            "%s: exists and is not a regular file, a FIFO or a character device; refusing to write "
                            "over it",
                            path);
    out->path = dup_string(path, 0, err);
    if (!out->path) return HK_ERR_NOMEM;
    const int fd = open(path, O_WRONLY);
    out->fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!out->fp) {
        hk_error_set(err, HK_ERR_IO, "%s: cannot open output file: %s", path, strerror(errno));
        if (fd >= 0) close(fd);
        hk_outfile_abort(out);
        return HK_ERR_IO;
    }
    return HK_OK;
}

hk_Status hk_outfile_open(hk_OutFile *out, const char *path, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    if (!path || !*path) return hk_error_set(err, HK_ERR_IO, "empty output file name");
    struct stat target;
    if (stat(path, &target) == 0 && !S_ISREG(target.st_mode)) return open_in_place(out, path, &target, err);
    out->path = follow_links(path, err);
    if (!out->path) return err ? err->code : HK_ERR_IO;
    /* "<path>.tmp-XXXXXX" lives in the same folder, so rename() is atomic. */
    out->tmp_path = dup_string(out->path, 12, err);
    if (!out->tmp_path) {
        hk_outfile_abort(out);
        return HK_ERR_NOMEM;
    }
    strcat(out->tmp_path, ".tmp-XXXXXX");
    int fd = create_registered(out->tmp_path, strlen(out->tmp_path) - 6);
    if (fd < 0) {
        hk_error_set(err, HK_ERR_IO, "%s: cannot create output file: %s", path, strerror(errno));
        free(out->tmp_path);
        out->tmp_path = NULL;
        hk_outfile_abort(out);
        return HK_ERR_IO;
    }
    /* Created private (0600); give it the permissions an ordinary new file would
     * have, or those of the file it replaces. */
    struct stat old;
    mode_t mode;
    if (stat(out->path, &old) == 0) {
        mode = old.st_mode & 07777;
    } else {
        mode_t mask = umask(0);
        umask(mask);
        mode = 0666 & ~mask;
    }
    fchmod(fd, mode);
    out->fp = fdopen(fd, "wb");
    if (!out->fp) {
        close(fd);
        hk_error_set(err, HK_ERR_IO, "%s: cannot open output file: %s", path, strerror(errno));
        hk_outfile_abort(out);
        return HK_ERR_IO;
    }
    return HK_OK;
}

hk_Status hk_outfile_commit(hk_OutFile *out, hk_Error *err)
{
    hk_Status st = HK_OK;
    if (!out->fp) return hk_error_set(err, HK_ERR_IO, "output file is not open");
    /* A FIFO or a device written in place has nothing to sync (fsync says EINVAL). */
    int bad = ferror(out->fp) || fflush(out->fp) != 0 || (out->tmp_path && fsync(fileno(out->fp)) != 0);
    int saved = errno;
    if (fclose(out->fp) != 0 && !bad) {
        bad = 1;
        saved = errno;
    }
    out->fp = NULL;
    if (bad) {
        st = hk_error_set(err, HK_ERR_IO, "%s: write failed: %s", out->path, strerror(saved));
    } else if (out->tmp_path && rename(out->tmp_path, out->path) != 0) {
        st = hk_error_set(err, HK_ERR_IO, "%s: cannot replace file: %s", out->path, strerror(errno));
    }
    if (out->tmp_path) {
        if (st != HK_OK) unlink(out->tmp_path);
        slot_release(out->tmp_path);
    }
    free(out->tmp_path);
    free(out->path);
    out->tmp_path = out->path = NULL;
    return st;
}

void hk_outfile_abort(hk_OutFile *out)
{
    if (out->fp) {
        fclose(out->fp);
        out->fp = NULL;
    }
    if (out->tmp_path) {
        unlink(out->tmp_path);
        slot_release(out->tmp_path);
    }
    free(out->tmp_path);
    free(out->path);
    out->tmp_path = out->path = NULL;
}
