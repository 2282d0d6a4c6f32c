/* Grows a head of hair from a setup file and renders it: hairkit's main path through
 * the library in one page (docs/library.md). The same as `hairkit run SETUP -o OUT`,
 * without the options.
 *
 *     grow_and_render SETUP.txt OUT.png [HAIRS_PER_CM2]
 *
 * HAIRS_PER_CM2 replaces the hairstyle's HairDensity (a small one runs in a second). */
#include <stdio.h>
#include <stdlib.h>

#include <hairkit/hairkit.h>

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: %s SETUP.txt OUT.png [HAIRS_PER_CM2]\n", argv[0]);
        return 2;
    }
    printf("hairkit %s\n", hk_version());

    /* Every call that can fail returns an hk_Status (HK_OK is 0) and fills err. */
    hk_Error err;
    hk_Setup setup;
    if (hk_setup_load(argv[1], &setup, &err) != HK_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    hk_Hairstyle style = hk_default_hairstyle();
    hk_Visuality colours = hk_default_visuality();
    hk_CollisionSet collision = {0}; /* the collision shapes (body envelopes) */
    hk_Mesh wick = {0}, head = {0};
    hk_Groom groom = {0};
    hk_HairFile hair = {0};
    hk_Canvas picture = {0};

    /* The setup's files: hairstyle, collision shapes, colours, the wick (the scalp the
     * hair grows from) and the head. Optional ones are NULL when the setup has none. */
    hk_Status st = hk_hairstyle_load(setup.hairstyle, &style, &err);
    if (st == HK_OK && argc == 4) {
        style.interpolation.hair_density = strtod(argv[3], NULL);
        if (!(style.interpolation.hair_density > 0))
            st = hk_error_set(&err, HK_ERR_INVALID, "bad density '%s'", argv[3]);
    }
    if (st == HK_OK && setup.collision) st = hk_collision_load(setup.collision, &collision, &err);
    if (st == HK_OK && setup.visuality) st = hk_visuality_load(setup.visuality, &colours, &err);
    if (st == HK_OK) st = hk_obj_load(setup.wick_model, &wick, &err);
    if (st == HK_OK && setup.head_model) st = hk_obj_load(setup.head_model, &head, &err);

    /* Grow: one guide strand per wick vertex, solved as a Super-Helix at rest under
     * gravity and the collision shapes (in parallel), then HairDensity strands per cm^2
     * interpolated between the guides; then the whole groom as cyHair data. */
    hk_GroomDef grow = hk_default_groom_def();
    if (st == HK_OK)
        st = hk_groom_grow(&style.strand, &style.interpolation, collision.shapes, collision.count, &wick, &grow, &groom,
                           &err);
    if (st == HK_OK) st = hk_groom_to_hair(&groom, &style.strand, &hair, &err);

    /* Render over the head (Kajiya-Kay shading, deep opacity shadows) and save. */
    hk_RenderDef view = hk_default_render_def();
    view.width = 800;
    view.height = 600;
    if (st == HK_OK) st = hk_render(&hair, setup.head_model ? &head : NULL, &colours, &view, &picture, NULL, &err);
    if (st == HK_OK) st = hk_render_write_png(&picture, argv[2], &err);

    if (st == HK_OK)
        printf("%d guides and %d strands of %d points: %s\n", groom.guide_count, groom.strand_count,
               groom.points_per_strand, argv[2]);
    else
        fprintf(stderr, "%s\n", err.message);
    hk_canvas_free(&picture);
    hk_hair_free(&hair);
    hk_groom_free(&groom);
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
    hk_collision_free(&collision);
    hk_hairstyle_free(&style);
    hk_setup_free(&setup);
    return st == HK_OK ? 0 : 1;
}
