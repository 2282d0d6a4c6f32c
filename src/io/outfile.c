/* Atomic output files: temporary name in the same folder, then rename (see outfile.h). */
#include "hairkit/outfile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *dup_string(const char *s, size_t extra, hk_Error *err)
{
    size_t n = strlen(s);
    char *d = hk_alloc_array(n + extra + 1, 1, err);
    if (d) memcpy(d, s, n + 1);
    return d;
}

hk_Status hk_outfile_open(hk_OutFile *out, const char *path, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    if (!path || !*path) return hk_error_set(err, HK_ERR_IO, "empty output file name");
    out->path = dup_string(path, 0, err);
    /* "<path>.tmp-XXXXXX" lives in the same folder, so rename() is atomic. */
    out->tmp_path = dup_string(path, 12, err);
    if (!out->path || !out->tmp_path) {
        hk_outfile_abort(out);
        return HK_ERR_NOMEM;
    }
    strcat(out->tmp_path, ".tmp-XXXXXX");
    int fd = mkstemp(out->tmp_path);
    if (fd < 0) {
        hk_error_set(err, HK_ERR_IO, "%s: cannot create output file: %s", path, strerror(errno));
        free(out->tmp_path);
        out->tmp_path = NULL;
        hk_outfile_abort(out);
        return HK_ERR_IO;
    }
    /* mkstemp makes the file private (0600); give it the permissions an ordinary new
     * file would have, or those of the file it replaces. */
    struct stat old;
    mode_t mode;
    if (stat(path, &old) == 0) {
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
    int bad = ferror(out->fp) || fflush(out->fp) != 0 || fsync(fileno(out->fp)) != 0;
    int saved = errno;
    if (fclose(out->fp) != 0 && !bad) {
        bad = 1;
        saved = errno;
    }
    out->fp = NULL;
    if (bad) {
        st = hk_error_set(err, HK_ERR_IO, "%s: write failed: %s", out->path, strerror(saved));
    } else if (rename(out->tmp_path, out->path) != 0) {
        st = hk_error_set(err, HK_ERR_IO, "%s: cannot replace file: %s", out->path, strerror(errno));
    }
    if (st != HK_OK) unlink(out->tmp_path);
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
    if (out->tmp_path) unlink(out->tmp_path);
    free(out->tmp_path);
    free(out->path);
    out->tmp_path = out->path = NULL;
}
