/* Files watched while the viewer runs (issue 16): the shader files given by the setup
 * or the command line, compiled again when they change (the old programs kept if the
 * new ones fail), and the hairstyle file, whose guides are solved again to show the new
 * rest shape (or a new simulation from it). Polled once a second by their modification
 * time: no inotify, the same code everywhere. */
#define _XOPEN_SOURCE 700 /* st_mtim */
#include <stdio.h>
#include <sys/stat.h>

#include "viewer/viewer_internal.h"

#define WATCH_PERIOD 1.0 /* seconds between polls */

/* The file's modification time in nanoseconds, -1 when it cannot be read. */
static long long mtime(const char *path)
{
    struct stat s;
    if (!path || stat(path, &s) != 0) return -1;
    return (long long)s.st_mtim.tv_sec * 1000000000LL + (long long)s.st_mtim.tv_nsec;
}

static const char *hairstyle_path(const hk_Viewer *v)
{
    const hk_Scene *sc = v->in->scene;
    return sc && !sc->setup.load && (sc->parts & HK_SCENE_HAIRSTYLE) ? sc->setup.hairstyle : NULL;
}

void hk_viewer_watch_start(hk_Viewer *v, double now)
{
    v->watch_wall = now;
    for (int k = 0; k < HK_VIEW_SHADER_COUNT; k++) v->watched[k] = mtime(v->in->shader[k]);
    v->watched[HK_VIEW_SHADER_COUNT] = mtime(hairstyle_path(v));
}

/* The hair grown again from the scene's (new) hairstyle, as `hairkit view SETUP` grew it
 * first; 0 on failure (message printed, the hair shown kept). */
static int regrow_static(hk_Viewer *v)
{
    hk_Error err;
    hk_HairFile hair = {0};
    hk_SceneHairReport report;
    const hk_GroomDef go = hk_default_groom_def();
    if (hk_scene_hair(v->in->scene, &go, &hair, &report, &err) != HK_OK) {
        fprintf(stderr, "hairkit view: %s\n", err.message);
        return 0;
    }
    hk_hair_free(&v->own_hair);
    v->own_hair = hair;
    return hk_viewer_set_hair(v, &v->own_hair, report.guides);
}

/* The hairstyle file changed: read it, then solve the guides again (and start the
 * simulation again from them). A file that does not read, or guides that cannot be
 * solved, leave what is shown as it was. */
static void reload_hairstyle(hk_Viewer *v, const char *path)
{
    hk_Scene *sc = v->in->scene;
    hk_Error err;
    hk_Hairstyle style;
    if (hk_hairstyle_load(path, &style, &err) != HK_OK) {
        fprintf(stderr, "hairkit view: %s (the hairstyle shown is kept)\n", err.message);
        return;
    }
    const hk_Hairstyle old = sc->style;
    sc->style = style;
    const int ok = v->live ? hk_viewer_live_restart(v) : regrow_static(v);
    if (ok) {
        hk_hairstyle_free((hk_Hairstyle *)&old);
        if (!v->in->quiet) fprintf(stderr, "hairkit view: %s changed: guides solved again\n", path);
    } else {
        sc->style = old;
        hk_hairstyle_free(&style);
    }
}

int hk_viewer_watch(hk_Viewer *v, double now)
{
    if (now - v->watch_wall < WATCH_PERIOD) return 1;
    v->watch_wall = now;
    int shaders = 0;
    for (int k = 0; k < HK_VIEW_SHADER_COUNT; k++) {
        const long long t = mtime(v->in->shader[k]);
        shaders |= t != v->watched[k];
        v->watched[k] = t;
    }
    if (shaders && hk_viewer_load_programs(v) && !v->in->quiet)
        fprintf(stderr, "hairkit view: shaders changed on disk: compiled again\n");
    const char *style = hairstyle_path(v);
    const long long t = mtime(style);
    if (t != v->watched[HK_VIEW_SHADER_COUNT] && t >= 0) reload_hairstyle(v, style);
    v->watched[HK_VIEW_SHADER_COUNT] = t;
    return 1;
}
