/* Scenes and files shared by the simulation tests (test_hair_sim.c, test_sim_frames.c). */
#include "hk_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *hk_test_read_file(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    *size = (size_t)ftell(fp);
    rewind(fp);
    char *data = malloc(*size + 1);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, *size, fp), *size);
    fclose(fp);
    data[*size] = '\0';
    return data;
}

const char *hk_test_light_setup(void)
{
    size_t size;
    char *style = hk_test_read_file(HK_SOURCE_DIR "/examples/default/hairstyle.txt", &size);
    char *line = strstr(style, "\nHairDensity");
    assert_non_null(line);
    char *end = strchr(line + 1, '\n');
    assert_non_null(end);
    char *text = malloc(size + 64);
    assert_non_null(text);
    snprintf(text, size + 64, "%.*s\nHairDensity 4%s", (int)(line - style), style, end);
    const char *style_path = hk_test_write_text("hairstyle.txt", text);
    char setup[4096];
    snprintf(setup, sizeof setup,
             "HairstyleInfo \"%s\"\nCollisionInfo \"%s/examples/default/collision.txt\"\n"
             "VisualityInfo \"%s/examples/default/visuality.txt\"\nHeadModel \"%s/assets/head.obj\"\n"
             "WickModel \"%s/assets/wick-200.obj\"\n",
             style_path, HK_SOURCE_DIR, HK_SOURCE_DIR, HK_SOURCE_DIR, HK_SOURCE_DIR);
    free(style);
    free(text);
    return hk_test_write_text("setup.txt", setup);
}
