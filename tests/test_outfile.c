/* Atomic output files (src/io/outfile.c) on what is not an ordinary new or old file:
 * symbolic links are followed (the link stays, its target is replaced), FIFOs and
 * character devices are written in place (never replaced by a regular file), folders
 * refused; and the temporaries of a process killed by SIGINT or SIGTERM removed. */
#define _XOPEN_SOURCE 700 /* mknod, symlink */
#include "hk_test.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/outfile.h"

static const char *tmp_path(const char *name)
{
    static char buf[4][600];
    static int next;
    char *p = buf[next++ % 4];
    snprintf(p, 600, "%s/%s", hk_test_tmpdir(), name);
    return p;
}

static hk_Status write_text(const char *path, const char *text, hk_Error *err)
{
    hk_OutFile out;
    hk_Status st = hk_outfile_open(&out, path, err);
    if (st != HK_OK) return st;
    fputs(text, out.fp);
    return hk_outfile_commit(&out, err);
}

/* Number of NAME.tmp-XXXXXX files in the test's folder. */
static int temporaries(void)
{
    DIR *d = opendir(hk_test_tmpdir());
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

static void test_symlinks_followed(void **state)
{
    (void)state;
    hk_Error err;
    const char *target = hk_test_write_text("target.txt", "old\n");
    const char *link = tmp_path("link.txt");
    assert_int_equal(symlink("target.txt", link), 0); /* relative to the link's folder */
    assert_int_equal(write_text(link, "new\n", &err), HK_OK);
    struct stat sb;
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode)); /* the link was replaced by a regular file before */
    size_t n;
    char *text = hk_test_read_file(target, &n);
    assert_string_equal(text, "new\n");
    free(text);
    /* A chain of two links, the last one dangling: the file it names is made. */
    const char *chain = tmp_path("chain.txt");
    assert_int_equal(symlink(link, chain), 0);
    const char *dangling = tmp_path("dangling.txt");
    assert_int_equal(symlink("made-by-write.txt", dangling), 0);
    assert_int_equal(write_text(chain, "chained\n", &err), HK_OK);
    text = hk_test_read_file(target, &n);
    assert_string_equal(text, "chained\n");
    free(text);
    assert_int_equal(write_text(dangling, "made\n", &err), HK_OK);
    assert_int_equal(lstat(dangling, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    text = hk_test_read_file(tmp_path("made-by-write.txt"), &n);
    assert_string_equal(text, "made\n");
    free(text);
    /* A loop of links. */
    const char *loop = tmp_path("loop.txt");
    assert_int_equal(symlink("loop.txt", loop), 0);
    assert_int_equal(write_text(loop, "x", &err), HK_ERR_IO);
    hk_assert_contains(err.message, "loop.txt: too many levels of symbolic links");
    assert_int_equal(temporaries(), 0);
}

static void test_fifo_written_in_place(void **state)
{
    (void)state;
    hk_Error err;
    const char *fifo = tmp_path("pipe");
    assert_int_equal(mkfifo(fifo, 0600), 0);
    /* A reader first, so that opening the FIFO for writing does not wait. */
    const int rd = open(fifo, O_RDONLY | O_NONBLOCK);
    assert_true(rd >= 0);
    assert_int_equal(write_text(fifo, "through the pipe\n", &err), HK_OK);
    char buf[64] = {0};
    assert_int_equal(read(rd, buf, sizeof buf - 1), 17);
    assert_string_equal(buf, "through the pipe\n");
    close(rd);
    struct stat sb;
    assert_int_equal(lstat(fifo, &sb), 0);
    assert_true(S_ISFIFO(sb.st_mode)); /* was renamed over by a regular file */
    /* A link to the FIFO: the FIFO is written, the link stays. */
    const char *link = tmp_path("pipe-link");
    assert_int_equal(symlink(fifo, link), 0);
    const int rd2 = open(fifo, O_RDONLY | O_NONBLOCK);
    assert_true(rd2 >= 0);
    assert_int_equal(write_text(link, "again\n", &err), HK_OK);
    assert_int_equal(read(rd2, buf, sizeof buf - 1), 6);
    close(rd2);
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    /* Aborting an in-place output leaves the FIFO there. */
    const int rd3 = open(fifo, O_RDONLY | O_NONBLOCK);
    hk_OutFile out;
    assert_int_equal(hk_outfile_open(&out, fifo, &err), HK_OK);
    hk_outfile_abort(&out);
    close(rd3);
    assert_int_equal(lstat(fifo, &sb), 0);
    assert_true(S_ISFIFO(sb.st_mode));
    assert_int_equal(temporaries(), 0);
}

/* A character device of our own (the null device's numbers), not /dev/null itself:
 * the unfixed code, run as root, replaced the device node. Needs the right to make
 * device nodes (root); skipped without it. */
static void test_character_device_written_in_place(void **state)
{
    (void)state;
    hk_Error err;
    const char *dev = tmp_path("null");
    if (mknod(dev, S_IFCHR | 0666, makedev(1, 3)) != 0) {
        print_message("no device nodes here (%s): skipped\n", strerror(errno));
        skip();
    }
    assert_int_equal(write_text(dev, "into the void\n", &err), HK_OK);
    struct stat sb;
    assert_int_equal(lstat(dev, &sb), 0);
    assert_true(S_ISCHR(sb.st_mode));
    unlink(dev);
    assert_int_equal(temporaries(), 0);
}

static void test_folder_refused(void **state)
{
    (void)state;
    hk_Error err;
    const char *dir = tmp_path("folder");
    assert_int_equal(mkdir(dir, 0700), 0);
    assert_int_equal(write_text(dir, "x", &err), HK_ERR_IO);
    hk_assert_contains(err.message, "folder: is a folder, not a file");
    struct stat sb;
    assert_int_equal(stat(dir, &sb), 0);
    assert_true(S_ISDIR(sb.st_mode));
    assert_int_equal(rmdir(dir), 0);
    assert_int_equal(temporaries(), 0);
}

/* A child with the handlers writes `done` (committed), then opens two outputs and
 * kills itself with `sig` while they are open. */
static void killed_while_writing(int sig, const char *done, const char *a, const char *b)
{
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        hk_outfile_cleanup_on_signals();
        hk_Error err;
        hk_OutFile x, y;
        if (write_text(done, "complete\n", &err) != HK_OK || hk_outfile_open(&x, a, &err) != HK_OK ||
            hk_outfile_open(&y, b, &err) != HK_OK)
            _exit(3);
        fputs("half", x.fp);
        fflush(x.fp);
        kill(getpid(), sig);
        _exit(4); /* not reached: the signal ends the process */
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), sig); /* ended by the signal, as without the handler */
}

static void test_temporaries_removed_on_signals(void **state)
{
    (void)state;
    killed_while_writing(SIGTERM, tmp_path("done1.hair"), tmp_path("a1.hair"), tmp_path("b1.png"));
    assert_int_equal(temporaries(), 0);
    killed_while_writing(SIGINT, tmp_path("done2.hair"), tmp_path("a2.hair"), tmp_path("b2.png"));
    assert_int_equal(temporaries(), 0);
    /* What was committed before stays; the interrupted outputs were never made. */
    struct stat sb;
    assert_int_equal(stat(tmp_path("done2.hair"), &sb), 0);
    assert_int_equal(stat(tmp_path("a2.hair"), &sb), -1);
    /* A signal the program ignores stays ignored. */
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        signal(SIGINT, SIG_IGN);
        hk_outfile_cleanup_on_signals();
        kill(getpid(), SIGINT);
        _exit(0);
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_symlinks_followed),
        cmocka_unit_test(test_fifo_written_in_place),
        cmocka_unit_test(test_character_device_written_in_place),
        cmocka_unit_test(test_folder_refused),
        cmocka_unit_test(test_temporaries_removed_on_signals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
