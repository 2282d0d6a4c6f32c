/* hairkit's whole public API in one include: #include <hairkit/hairkit.h>. Each module
 * also has its own header, included here. docs/library.md shows how to build against
 * the installed library (pkg-config hairkit, or find_package(hairkit) in CMake). */
#ifndef HAIRKIT_HAIRKIT_H
#define HAIRKIT_HAIRKIT_H

#include "hairkit/canvas.h"
#include "hairkit/capture.h"
#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/curvefit.h"
#include "hairkit/dynamics.h"
#include "hairkit/export.h"
#include "hairkit/follicle_sampling.h"
#include "hairkit/groom.h"
#include "hairkit/hair_contacts.h"
#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/helicoid_hair.h"
#include "hairkit/image.h"
#include "hairkit/io.h"
#include "hairkit/live_sim.h"
#include "hairkit/mesh.h"
#include "hairkit/motion.h"
#include "hairkit/optimize.h"
#include "hairkit/render.h"
#include "hairkit/rng.h"
#include "hairkit/rod.h"
#include "hairkit/scene.h"
#include "hairkit/simulate.h"
#include "hairkit/simulation_file.h"
#include "hairkit/statics.h"
#include "hairkit/vecmath.h"
#include "hairkit/version.h"

#endif /* HAIRKIT_HAIRKIT_H */
