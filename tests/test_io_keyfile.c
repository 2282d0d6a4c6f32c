/* The `Key value...` reader (src/io/keyfile.c): tokenising rules, line ends, refused
 * files, typed values with their file:line messages, key checks and path resolution. */
#include "hk_test.h"

#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hairkit/io.h"
#include "io/keyfile.h"

/* Reads `text` as file `name`; fails the test when that does not succeed. Returns
 * the file's path. */
static const char *read_ok(const char *name, const char *text, hk_KeyFile *kf)
{
    hk_Error err;
    const char *path = hk_test_write_text(name, text);
    hk_Status st = hk_keyfile_read(path, kf, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    return path;
}

/* Reading `size` bytes as file `name` fails with `code` and a message containing
 * `phrase`; kf is left with nothing to free. */
static void read_fails(const char *name, const void *data, size_t size, hk_Status code, const char *phrase)
{
    hk_KeyFile kf;
    hk_Error err;
    memset(&kf, 0x5A, sizeof kf);
    err.message[0] = '\0';
    hk_Status st = hk_keyfile_read(hk_test_write_file(name, data, size), &kf, &err);
    if (st != code) print_error("status %d, message '%s'\n", st, err.message);
    assert_int_equal(st, code);
    hk_assert_contains(err.message, phrase);
    assert_null(kf.path);
    assert_null(kf.text);
    assert_null(kf.lines);
    assert_null(kf.tokens);
    assert_int_equal(kf.line_count, 0);
}

static void read_text_fails(const char *name, const char *text, hk_Status code, const char *phrase)
{
    read_fails(name, text, strlen(text), code, phrase);
}

static void assert_line(const hk_KeyLine *kl, int line, const char *key, int count)
{
    assert_int_equal(kl->line, line);
    assert_string_equal(kl->key, key);
    assert_int_equal(kl->count, count);
}

static void test_tokens(void **state)
{
    (void)state;
    const char *text = "# header comment\n"
                       "\n"
                       "Path \"my hair/file #1.hair\"  # comment\n"
                       "Values\t1  2\t\t3#glued comment\n"
                       "   \t  \n"
                       "   # indented comment\n"
                       "Empty \"\" after\n"
                       "Quoted \"a b\"#c\n"
                       "  Indented   x\n"
                       "Lonely\n";
    hk_KeyFile kf;
    const char *path = read_ok("setup.txt", text, &kf);
    assert_string_equal(kf.path, path);
    assert_int_equal(kf.line_count, 6);
    assert_line(&kf.lines[0], 3, "Path", 1);
    assert_string_equal(kf.lines[0].values[0], "my hair/file #1.hair");
    assert_line(&kf.lines[1], 4, "Values", 3);
    assert_string_equal(kf.lines[1].values[0], "1");
    assert_string_equal(kf.lines[1].values[1], "2");
    assert_string_equal(kf.lines[1].values[2], "3");
    assert_line(&kf.lines[2], 7, "Empty", 2);
    assert_string_equal(kf.lines[2].values[0], "");
    assert_string_equal(kf.lines[2].values[1], "after");
    assert_line(&kf.lines[3], 8, "Quoted", 1);
    assert_string_equal(kf.lines[3].values[0], "a b");
    assert_line(&kf.lines[4], 9, "Indented", 1);
    assert_string_equal(kf.lines[4].values[0], "x");
    assert_line(&kf.lines[5], 10, "Lonely", 0);
    hk_keyfile_free(&kf);
    assert_null(kf.path);
    hk_keyfile_free(&kf); /* twice is harmless */

    /* Only comments and blanks: a valid file with no lines. */
    read_ok("comments.txt", "# nothing\n\n   \t\n# here\n", &kf);
    assert_int_equal(kf.line_count, 0);
    hk_keyfile_free(&kf);
}

static void test_line_ends(void **state)
{
    (void)state;
    hk_KeyFile kf;
    /* CRLF, no final line end, blank CRLF lines: no '\r' may stick to a value. */
    read_ok("crlf.txt", "A 1\r\n\r\nB \"x y\"\r\nC 3 4", &kf);
    assert_int_equal(kf.line_count, 3);
    assert_line(&kf.lines[0], 1, "A", 1);
    assert_string_equal(kf.lines[0].values[0], "1");
    assert_line(&kf.lines[1], 3, "B", 1);
    assert_string_equal(kf.lines[1].values[0], "x y");
    assert_line(&kf.lines[2], 4, "C", 2);
    assert_string_equal(kf.lines[2].values[1], "4");
    hk_keyfile_free(&kf);
    /* Old Mac line ends (lone CR) and a mix of all three. */
    read_ok("cr.txt", "A 1\rB 2\n\rC 3\r\nD", &kf);
    assert_int_equal(kf.line_count, 4);
    assert_line(&kf.lines[0], 1, "A", 1);
    assert_line(&kf.lines[1], 2, "B", 1);
    assert_string_equal(kf.lines[1].values[0], "2");
    assert_line(&kf.lines[2], 4, "C", 1);
    assert_line(&kf.lines[3], 5, "D", 0);
    hk_keyfile_free(&kf);
    /* A single key without any line end, and a UTF-8 byte-order mark. */
    read_ok("one.txt", "\xEF\xBB\xBFKey value", &kf);
    assert_int_equal(kf.line_count, 1);
    assert_line(&kf.lines[0], 1, "Key", 1);
    hk_keyfile_free(&kf);
    /* Line numbers in messages count the same line ends. */
    read_text_fails("q.txt", "A 1\r\nB 2\rC \"open\n", HK_ERR_PARSE, "q.txt:3: unterminated double quote");
}

static void test_quotes(void **state)
{
    (void)state;
    read_text_fails("quote.txt", "A 1\nB \"unterminated # not a comment\nC 3\n", HK_ERR_PARSE,
                    "quote.txt:2: unterminated double quote");
    /* A quote does not run on into the next line. */
    read_text_fails("quote.txt", "A \"x\nB y\"\n", HK_ERR_PARSE, "quote.txt:1: unterminated");
    read_text_fails("quote.txt", "A 1\nA ab\"c d\"\n", HK_ERR_PARSE, "quote.txt:2: misplaced double quote");
    read_text_fails("quote.txt", "A \"c d\"e\n", HK_ERR_PARSE, "quote.txt:1: misplaced double quote");
    /* A '#' after a closing quote starts a comment, as after a bare value. */
    hk_KeyFile kf;
    read_ok("quote.txt", "A \"c d\"# e \"f\n", &kf);
    assert_int_equal(kf.lines[0].count, 1);
    hk_keyfile_free(&kf);
}

static void test_refused_files(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    assert_int_equal(hk_keyfile_read("/nonexistent/dir/setup.txt", &kf, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/dir/setup.txt: cannot open");
    assert_null(kf.path);
    assert_int_equal(hk_keyfile_read(hk_test_tmpdir(), &kf, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "is a folder");
    /* A FIFO without a writer: must be refused at once, not block forever. */
    char fifo[600];
    snprintf(fifo, sizeof fifo, "%s/fifo.txt", hk_test_tmpdir());
    assert_int_equal(mkfifo(fifo, 0600), 0);
    assert_int_equal(hk_keyfile_read(fifo, &kf, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "fifo.txt: not a regular file");
    unlink(fifo);

    read_fails("empty.txt", "", 0, HK_ERR_PARSE, "empty.txt: file is empty");
    static const char nul[] = "A 1\nB 2\nC \0 3\n";
    read_fails("nul.txt", nul, sizeof nul - 1, HK_ERR_PARSE, "nul.txt: not a text file (binary data at line 3)");
    read_text_fails("ctl.txt", "A 1\r\nB \x01\n", HK_ERR_PARSE, "ctl.txt: not a text file (binary data at line 2)");
    read_text_fails("del.txt", "A \x7F\n", HK_ERR_PARSE, "(binary data at line 1)");
    read_text_fails("esc.txt", "A 1\rB 2\r\x1B[0m", HK_ERR_PARSE, "(binary data at line 3)");
    static const char utf16[] = "\xFF\xFE"
                                "A\0 \0"
                                "1\0";
    read_fails("utf16.txt", utf16, sizeof utf16 - 1, HK_ERR_PARSE, "utf16.txt: not a text file (UTF-16");
    /* Form feeds, vertical tabs and non-ASCII text (UTF-8 comments) are text. */
    read_ok("ok.txt", "A\f1\v2 # caf\xC3\xA9\n", &kf);
    assert_int_equal(kf.lines[0].count, 2);
    hk_keyfile_free(&kf);
}

/* Exactly HK_MAX_INPUT_FILE_BYTES is accepted, one byte more is refused, and a huge
 * sparse file is refused without being read. */
static void test_size_limit(void **state)
{
    (void)state;
    const size_t limit = (size_t)HK_MAX_INPUT_FILE_BYTES;
    char *big = malloc(limit + 1);
    assert_non_null(big);
    memset(big, ' ', limit + 1);
    memcpy(big, "Key 1\n", 6);
    memcpy(big + limit - 6, "Tip 2\n", 6);
    hk_KeyFile kf;
    hk_Error err;
    assert_int_equal(hk_keyfile_read(hk_test_write_file("limit.txt", big, limit), &kf, &err), HK_OK);
    assert_int_equal(kf.line_count, 2);
    assert_string_equal(kf.lines[1].key, "Tip");
    hk_keyfile_free(&kf);
    read_fails("over.txt", big, limit + 1, HK_ERR_PARSE, "over.txt: file is larger than");
    free(big);

    char path[600];
    snprintf(path, sizeof path, "%s/huge.txt", hk_test_tmpdir());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    /* 8 GiB, sparse: more than HK_MAX_ALLOCATION, so a reader that trusted the size
     * and allocated first would fail differently (HK_ERR_NOMEM). */
    assert_int_equal(fseek(f, (long)1 << 33, SEEK_SET), 0);
    fputc('\n', f);
    assert_int_equal(fclose(f), 0);
    assert_int_equal(hk_keyfile_read(path, &kf, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "huge.txt: file is larger than the 16777216 bytes allowed");
    unlink(path);
}

/* Files that report no size (Linux /proc) are read to their end all the same. */
static void test_unsized_file(void **state)
{
    (void)state;
    if (access("/proc/self/status", R_OK) != 0) skip();
    hk_KeyFile kf;
    hk_Error err;
    assert_int_equal(hk_keyfile_read("/proc/self/status", &kf, &err), HK_OK);
    struct stat sb;
    assert_int_equal(stat("/proc/self/status", &sb), 0);
    assert_int_equal(sb.st_size, 0);
    assert_true(kf.line_count > 20); /* well beyond a first small buffer */
    assert_string_equal(kf.lines[0].key, "Name:");
    int pid_line = 0;
    for (int i = 0; i < kf.line_count; i++)
        if (!strcmp(kf.lines[i].key, "Pid:")) pid_line = i;
    assert_true(pid_line > 0);
    assert_int_equal(atol(kf.lines[pid_line].values[0]), (long)getpid());
    hk_keyfile_free(&kf);
}

/* A one-line file "Key v1 v2 ..." read into kf; its line is kf->lines[0]. */
static const hk_KeyLine *one_line(const char *text, hk_KeyFile *kf)
{
    read_ok("values.txt", text, kf);
    assert_int_equal(kf->line_count, 1);
    return &kf->lines[0];
}

static void test_doubles(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    double v[6];
    const hk_KeyLine *kl = one_line("Sphere -0.02 +0.068 .5 5. 1E-3 -7e+2\n", &kf);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 6, v, &err), HK_OK);
    hk_assert_near(v[0], -0.02, 0);
    hk_assert_near(v[1], 0.068, 0);
    hk_assert_near(v[2], 0.5, 0);
    hk_assert_near(v[3], 5.0, 0);
    hk_assert_near(v[4], 1e-3, 0);
    hk_assert_near(v[5], -700.0, 0);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 7, v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "values.txt:1: expected 7 numbers after 'Sphere', got 6");
    hk_keyfile_free(&kf);

    kl = one_line("\n\nSphere 1 2\n", &kf);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 3, v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "values.txt:3: expected 3 numbers after 'Sphere', got 2");
    assert_int_equal(hk_keyline_doubles(&kf, kl, 1, v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "expected 1 number after 'Sphere', got 2");
    hk_keyfile_free(&kf);

    static const char *const bad[] = {"1.0abc", "nan", "NaN", "inf",   "-inf", "Infinity", "0x1p3",
                                      "0x10",   "1e",  "1e+", ".",     "+",    "-",        "1.2.3",
                                      "1e5.5",  "--1", "1,5", "1 .5x", "e5",   "1d0",      "\"\""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[64];
        snprintf(text, sizeof text, "Density %s\n", bad[i]);
        kl = one_line(text, &kf);
        hk_Status st = hk_keyline_doubles(&kf, kl, kl->count, v, &err);
        if (st != HK_ERR_PARSE) print_error("'%s' was accepted\n", bad[i]);
        assert_int_equal(st, HK_ERR_PARSE);
        hk_assert_contains(err.message, "values.txt:1: '");
        hk_assert_contains(err.message, "' is not a finite number (value ");
        hk_assert_contains(err.message, " of 'Density')");
        hk_keyfile_free(&kf);
    }
    kl = one_line("Young 1 1e400\n", &kf);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 2, v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message,
                       "values.txt:1: '1e400' is out of the range of double precision (value 2 of 'Young')");
    hk_keyfile_free(&kf);
    kl = one_line("Young -1e-400\n", &kf);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 1, v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "'-1e-400' is out of the range");
    hk_keyfile_free(&kf);
    /* Zero, however written, is not an underflow. */
    kl = one_line("Young 0e-500 -0.000\n", &kf);
    assert_int_equal(hk_keyline_doubles(&kf, kl, 2, v, &err), HK_OK);
    assert_true(v[0] == 0.0 && v[1] == 0.0);
    hk_keyfile_free(&kf);
}

/* Numbers read the same whatever LC_NUMERIC a host program chose. */
static void test_locale(void **state)
{
    (void)state;
    static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8",  "fr_FR.UTF-8",
                                        "fr_FR.utf8",  "nl_NL.UTF-8", "nl_NL.utf8"};
    const char *found = NULL;
    for (size_t i = 0; i < sizeof names / sizeof names[0] && !found; i++)
        if (setlocale(LC_NUMERIC, names[i]) && strcmp(localeconv()->decimal_point, ",") == 0) found = names[i];
    if (!found) {
        setlocale(LC_NUMERIC, "C");
        skip(); /* no locale with a decimal comma installed */
    }
    hk_KeyFile kf;
    hk_Error err;
    double v[2];
    const hk_KeyLine *kl = one_line("Gravity 9.81 +0.068\n", &kf);
    hk_Status st = hk_keyline_doubles(&kf, kl, 2, v, &err);
    setlocale(LC_NUMERIC, "C");
    assert_int_equal(st, HK_OK);
    hk_assert_near(v[0], 9.81, 0);
    hk_assert_near(v[1], 0.068, 0);
    hk_keyfile_free(&kf);
}

static void test_double_list(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    double v[4];
    int got = -1;
    const hk_KeyLine *kl = one_line("HairLengths 0.1 0.2 0.3\n", &kf);
    assert_int_equal(hk_keyline_double_list(&kf, kl, 4, v, &got, &err), HK_OK);
    assert_int_equal(got, 3);
    hk_assert_near(v[2], 0.3, 0);
    assert_int_equal(hk_keyline_double_list(&kf, kl, 3, v, &got, &err), HK_OK);
    assert_int_equal(hk_keyline_double_list(&kf, kl, 2, v, &got, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "values.txt:1: 'HairLengths' has 3 values, at most 2 allowed");
    hk_keyfile_free(&kf);
    kl = one_line("HairLengths\n", &kf);
    assert_int_equal(hk_keyline_double_list(&kf, kl, 4, v, &got, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "values.txt:1: 'HairLengths' needs at least one number");
    hk_keyfile_free(&kf);
    kl = one_line("HairLengths 0.1 x\n", &kf);
    assert_int_equal(hk_keyline_double_list(&kf, kl, 4, v, &got, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "'x' is not a finite number (value 2 of 'HairLengths')");
    hk_keyfile_free(&kf);
}

static void test_int(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    long v = 0;
    static const struct {
        const char *text;
        long value;
    } good[] = {{"MaxIter 5", 5}, {"MaxIter +7", 7}, {"MaxIter 1", 1}, {"MaxIter 10", 10}, {"MaxIter 007", 7}};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        const hk_KeyLine *kl = one_line(good[i].text, &kf);
        assert_int_equal(hk_keyline_int(&kf, kl, 1, 10, &v, &err), HK_OK);
        assert_int_equal(v, good[i].value);
        hk_keyfile_free(&kf);
    }
    static const char *const not_whole[] = {"2.5", "1e3", "0x10", "ten", "5x", "-", "+"};
    for (size_t i = 0; i < sizeof not_whole / sizeof not_whole[0]; i++) {
        char text[64];
        snprintf(text, sizeof text, "Maxiter %s", not_whole[i]);
        const hk_KeyLine *kl = one_line(text, &kf);
        assert_int_equal(hk_keyline_int(&kf, kl, 1, 10, &v, &err), HK_ERR_PARSE);
        hk_assert_contains(err.message, "values.txt:1: '");
        hk_assert_contains(err.message, "' is not a whole number (value of 'Maxiter')");
        hk_keyfile_free(&kf);
    }
    static const char *const out_of_range[] = {"0", "11", "-3", "99999999999999999999999"};
    for (size_t i = 0; i < sizeof out_of_range / sizeof out_of_range[0]; i++) {
        char text[64], want[96];
        snprintf(text, sizeof text, "MaxIter %s", out_of_range[i]);
        snprintf(want, sizeof want, "values.txt:1: MaxIter must be in [1, 10], got %s", out_of_range[i]);
        const hk_KeyLine *kl = one_line(text, &kf);
        assert_int_equal(hk_keyline_int(&kf, kl, 1, 10, &v, &err), HK_ERR_INVALID);
        hk_assert_contains(err.message, want);
        hk_keyfile_free(&kf);
    }
    const hk_KeyLine *kl = one_line("MaxIter 1 2", &kf);
    assert_int_equal(hk_keyline_int(&kf, kl, 1, 10, &v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "expected one value after 'MaxIter', got 2");
    hk_keyfile_free(&kf);
}

static void test_bool(void **state)
{
    (void)state;
    static const struct {
        const char *word;
        int value;
    } words[] = {{"true", 1},  {"TRUE", 1},  {"True", 1}, {"yes", 1}, {"YeS", 1}, {"on", 1}, {"1", 1},
                 {"false", 0}, {"FALSE", 0}, {"no", 0},   {"No", 0},  {"off", 0}, {"0", 0}};
    hk_KeyFile kf;
    hk_Error err;
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++) {
        char text[64];
        snprintf(text, sizeof text, "Load %s\n", words[i].word);
        const hk_KeyLine *kl = one_line(text, &kf);
        int flag = -1;
        assert_int_equal(hk_keyline_bool(&kf, kl, &flag, &err), HK_OK);
        assert_int_equal(flag, words[i].value);
        hk_keyfile_free(&kf);
    }
    static const char *const bad[] = {"maybe", "2", "truex", "t", "\"\""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[64];
        snprintf(text, sizeof text, "\nLoad %s\n", bad[i]);
        const hk_KeyLine *kl = one_line(text, &kf);
        int flag = -1;
        assert_int_equal(hk_keyline_bool(&kf, kl, &flag, &err), HK_ERR_PARSE);
        hk_assert_contains(err.message, "values.txt:2: 'Load' must be true or false, got '");
        assert_int_equal(flag, -1);
        hk_keyfile_free(&kf);
    }
    const hk_KeyLine *kl = one_line("Load\n", &kf);
    int flag = -1;
    assert_int_equal(hk_keyline_bool(&kf, kl, &flag, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "values.txt:1: expected one value after 'Load', got 0");
    hk_keyfile_free(&kf);
}

static void test_string(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    const char *s = NULL;
    const hk_KeyLine *kl = one_line("SaveFile Hair/Hair1.hair # bare\n", &kf);
    assert_int_equal(hk_keyline_string(&kf, kl, &s, &err), HK_OK);
    assert_string_equal(s, "Hair/Hair1.hair");
    hk_keyfile_free(&kf);
    kl = one_line("HeadVert \"Assets/Shaders/Phong Shadow.vert\"\r\n", &kf);
    assert_int_equal(hk_keyline_string(&kf, kl, &s, &err), HK_OK);
    assert_string_equal(s, "Assets/Shaders/Phong Shadow.vert");
    hk_keyfile_free(&kf);
    /* Appendix B's own setup file has this slip: blanks without quotes. */
    kl = one_line("HeadVert Assets/Shaders/Phong Shadow.vert\n", &kf);
    assert_int_equal(hk_keyline_string(&kf, kl, &s, &err), HK_ERR_PARSE);
    hk_assert_contains(
        err.message,
        "values.txt:1: expected one value after 'HeadVert', got 2 (write a value with blanks in double quotes)");
    hk_keyfile_free(&kf);
}

static const hk_KeySpec specs[] = {
    {"HairLengths", "HairLength", 1},
    {"MaxIter", NULL, 0},
    {"Young", NULL, 1},
};

static void test_check_keys(void **state)
{
    (void)state;
    hk_KeyFile kf;
    hk_Error err;
    int line_of[3] = {-1, -1, -1};
    assert_int_equal(hk_keyspec_find(specs, 3, "hairlength"), 0);
    assert_int_equal(hk_keyspec_find(specs, 3, "HAIRLENGTHS"), 0);
    assert_int_equal(hk_keyspec_find(specs, 3, "Maxiter"), 1);
    assert_int_equal(hk_keyspec_find(specs, 3, "Max"), -1);
    assert_int_equal(hk_keyspec_find(specs, 3, "MaxIters"), -1);
    assert_int_equal(hk_keyspec_find(specs, 3, ""), -1);
    assert_true(hk_key_equal("Elipsoid", "ELIPSOID"));
    assert_false(hk_key_equal("Elipsoid", "Ellipsoid"));

    read_ok("keys.txt", "# c\nyoung 1\n\nhairlength 1 2\n", &kf);
    assert_int_equal(hk_keyfile_check_keys(&kf, specs, 3, "hairstyle", line_of, &err), HK_OK);
    assert_int_equal(line_of[0], 4);
    assert_int_equal(line_of[1], 0);
    assert_int_equal(line_of[2], 2);
    hk_keyfile_free(&kf);

    static const struct {
        const char *text, *message;
    } cases[] = {
        {"Young 1\nHairLengths 1\nFoo 2\n", "keys.txt:3: unknown key 'Foo' in a hairstyle file"},
        {"Young 1\nHairLengths 1\nYOUNG 2\n", "keys.txt:3: duplicate key 'Young' (first given at line 1)"},
        {"HairLength 1\nYoung 1\nHairLengths 1\n", "keys.txt:3: duplicate key 'HairLengths' (first given at line 1)"},
        {"HairLengths 1\nMaxIter 3\n", "keys.txt: missing required key 'Young'"},
        {"# only a comment\n", "keys.txt: missing required key 'HairLengths'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        read_ok("keys.txt", cases[i].text, &kf);
        assert_int_equal(hk_keyfile_check_keys(&kf, specs, 3, "hairstyle", line_of, &err), HK_ERR_PARSE);
        hk_assert_contains(err.message, cases[i].message);
        hk_keyfile_free(&kf);
    }
    read_ok("keys.txt", "Bar 1\n", &kf);
    assert_int_equal(hk_keyfile_check_keys(&kf, specs, 3, NULL, line_of, &err), HK_ERR_PARSE);
    assert_string_equal(strstr(err.message, "keys.txt:"), "keys.txt:1: unknown key 'Bar'");
    hk_keyfile_free(&kf);
}

static void test_resolve_path(void **state)
{
    (void)state;
    hk_Error err;
    hk_KeyFile kf;
    memset(&kf, 0, sizeof kf);
    static const struct {
        const char *file, *relative, *want;
    } cases[] = {
        {"scenes/coupe 1/setup.txt", "Hair/Hair1.hair", "scenes/coupe 1/Hair/Hair1.hair"},
        {"scenes/setup.txt", "../Assets/Head.obj", "scenes/../Assets/Head.obj"},
        {"/abs/setup.txt", "a.txt", "/abs/a.txt"},
        {"setup.txt", "Properties/Hairstyle/Hairstyle1.txt", "Properties/Hairstyle/Hairstyle1.txt"},
        {"scenes/setup.txt", "/usr/share/head.obj", "/usr/share/head.obj"},
        {"/setup.txt", "x", "/x"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[128];
        snprintf(path, sizeof path, "%s", cases[i].file);
        kf.path = path;
        char *r = hk_keyfile_resolve_path(&kf, cases[i].relative, &err);
        assert_non_null(r);
        assert_string_equal(r, cases[i].want);
        hk_free(r);
    }
    char path[] = "scenes/setup.txt";
    kf.path = path;
    assert_null(hk_keyfile_resolve_path(&kf, "", &err));
    hk_assert_contains(err.message, "scenes/setup.txt: empty path");

    /* Against a real file read from the temporary folder. */
    read_ok("setup.txt", "HairstyleInfo \"my styles/curly.txt\"\n", &kf);
    const char *value = NULL;
    assert_int_equal(hk_keyline_string(&kf, &kf.lines[0], &value, &err), HK_OK);
    char *r = hk_keyfile_resolve_path(&kf, value, &err);
    char want[700];
    snprintf(want, sizeof want, "%s/my styles/curly.txt", hk_test_tmpdir());
    assert_string_equal(r, want);
    hk_free(r);
    hk_keyfile_free(&kf);
}

static void test_error_helper(void **state)
{
    (void)state;
    hk_KeyFile kf;
    memset(&kf, 0, sizeof kf);
    char path[] = "dir/visuality.txt";
    kf.path = path;
    hk_Error err;
    assert_int_equal(hk_keyfile_error(&kf, 14, HK_ERR_INVALID, &err, "Glossiness must be > %d", 0), HK_ERR_INVALID);
    assert_string_equal(err.message, "dir/visuality.txt:14: Glossiness must be > 0");
    assert_int_equal(err.code, HK_ERR_INVALID);
    assert_int_equal(hk_keyfile_error(&kf, 0, HK_ERR_PARSE, &err, "missing"), HK_ERR_PARSE);
    assert_string_equal(err.message, "dir/visuality.txt: missing");
    assert_int_equal(hk_keyfile_error(&kf, 3, HK_ERR_PARSE, NULL, "no err"), HK_ERR_PARSE);
    /* A NULL hk_Error is allowed everywhere. */
    assert_int_equal(hk_keyfile_read("/nonexistent/x.txt", &kf, NULL), HK_ERR_IO);
}

/* Random mutations of a valid file: the reader never crashes, every accepted line has
 * a non-empty key and sane line numbers, every refusal has a message naming the file. */
static void test_fuzz(void **state)
{
    (void)state;
    static const char base[] = "# Setup\r\nLoad true\nSaveFile \"Hair/my hair #1.hair\" # c\n"
                               "\nValues 1 2\t3\rLast \"x\"";
    unsigned long long x = 0x9E3779B97F4A7C15ULL;
    int accepted = 0, refused = 0;
    for (int iter = 0; iter < 2000; iter++) {
        char buf[256];
        size_t len = sizeof base - 1;
        memcpy(buf, base, len);
        for (int e = 0; e < 1 + iter % 3; e++) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            size_t at = (size_t)(x % (len + 1));
            unsigned op = (unsigned)(x >> 40) % 4;
            if (op == 0 && at < len)
                buf[at] = (char)(x >> 48);
            else if (op == 1)
                len = at;
            else if (op == 2 && at < len)
                buf[at] = "\"#\r\n \t\0x"[(x >> 32) % 8];
            else if (len + 3 < sizeof buf) {
                memmove(buf + at + 3, buf + at, len - at);
                memcpy(buf + at, " \"#", 3);
                len += 3;
            }
        }
        hk_KeyFile kf;
        hk_Error err;
        err.message[0] = '\0';
        hk_Status st = hk_keyfile_read(hk_test_write_file("fuzz.txt", buf, len), &kf, &err);
        if (st == HK_OK) {
            int last = 0;
            for (int i = 0; i < kf.line_count; i++) {
                assert_true(kf.lines[i].line > last);
                last = kf.lines[i].line;
                assert_true(kf.lines[i].key[0] != '\0' || strchr(buf, '"') != NULL);
                for (int j = 0; j < kf.lines[i].count; j++) assert_null(strpbrk(kf.lines[i].values[j], "\r\n"));
            }
            hk_keyfile_free(&kf);
            accepted++;
        } else {
            assert_true(st == HK_ERR_PARSE);
            hk_assert_contains(err.message, "fuzz.txt:");
            assert_null(kf.text);
            refused++;
        }
    }
    print_message("keyfile fuzz: %d accepted, %d refused\n", accepted, refused);
    assert_true(accepted > 200 && refused > 200);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tokens),        cmocka_unit_test(test_line_ends),    cmocka_unit_test(test_quotes),
        cmocka_unit_test(test_refused_files), cmocka_unit_test(test_size_limit),   cmocka_unit_test(test_unsized_file),
        cmocka_unit_test(test_doubles),       cmocka_unit_test(test_locale),       cmocka_unit_test(test_double_list),
        cmocka_unit_test(test_int),           cmocka_unit_test(test_bool),         cmocka_unit_test(test_string),
        cmocka_unit_test(test_check_keys),    cmocka_unit_test(test_resolve_path), cmocka_unit_test(test_error_helper),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
