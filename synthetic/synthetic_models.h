/**
 * \file synthetic_models.h
 * \brief Synthetic polygon meshes of the thesis objects and of table-top distractors.
 *
 * All models are in metres, with the symmetry axis (if any) along z and the origin at the centre of
 * the model (the centre of the bounding box; for bodies of revolution the origin is on the axis,
 * see makeCylinder). Vertices are pcl::PointXYZ in mesh.cloud, faces are pcl::Vertices wound
 * counter-clockwise seen from outside (outward normals). All solids are closed.
 */
#pragma once

#include "synthetic/pose_error.h"

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief Axis-aligned box with side lengths sx, sy, sz (metres) centred at the origin.
 *  24 vertices (4 per face, not shared between faces) and 6 quads. */
pcl::PolygonMesh makeBox(double sx, double sy, double sz);

/** \brief The thesis's blue box "Box5": makeBox(0.14, 0.09, 0.05). */
pcl::PolygonMesh makeBox5();

/** \brief Closed frustum of a cone (a cylinder when bottom_radius == top_radius) along z.
 *
 * The base polygon has `segments` vertices, the first on the +x axis; z in [-height/2, height/2].
 * Faces: `segments` side quads, then `segments` bottom-cap triangles and `segments` top-cap
 * triangles fanned around a cap centre vertex (3 * segments faces).
 * Vertices (4 * segments + 2): bottom side ring, top side ring (shared by the side quads), bottom
 * cap ring, top cap ring (own copies), bottom centre, top centre.
 * The origin lies on the axis; for odd `segments` the bounding-box centre is therefore offset by
 * r (1 - cos(pi / segments)) / 2 along x (0.2 mm for EisKaffe).
 * \throws std::invalid_argument if segments < 3 or a size is not positive.
 */
pcl::PolygonMesh makeFrustum(double bottom_radius, double top_radius, double height, int segments);

/** \brief Closed cylinder of the given radius and height (metres), see makeFrustum. */
pcl::PolygonMesh makeCylinder(double radius, double height, int segments);

/** \brief "YellowRoundSalt": makeCylinder(0.045, 0.13, 32): 130 vertices, 96 faces
 *  (32 quads + 64 triangles). */
pcl::PolygonMesh makeYellowRoundSalt();

/** \brief "EisKaffe": makeCylinder(0.05, 0.15, 25): 102 vertices, 75 faces
 *  (25 quads + 50 triangles). */
pcl::PolygonMesh makeEisKaffe();

/** \brief Closed regular hexagonal prism along z, triangles only (metres).
 *
 * The hexagon has circumradius `circumradius` with a vertex on the +x axis; z in
 * [-height/2, height/2]. Faces (24 triangles): 6 side rectangles split into 2 triangles each (12),
 * then 6 bottom-cap and 6 top-cap triangles fanned around a centre vertex (12).
 * Vertices (38): 4 per side rectangle (24, not shared), then per cap 6 ring vertices + 1 centre.
 */
pcl::PolygonMesh makeHexPrism(double circumradius, double height);

/** \brief "Amicelly": makeHexPrism(0.04, 0.12): 38 vertices, 24 triangles. */
pcl::PolygonMesh makeAmicelly();

/** \brief A cup-like distractor: a closed frustum widening upwards (metres), see makeFrustum.
 *  Default: 24 segments, 98 vertices, 72 faces. */
pcl::PolygonMesh makeCup(double bottom_radius = 0.035, double top_radius = 0.045,
                         double height = 0.10, int segments = 24);

/** \brief An irregular distractor without symmetry: a base box (0.10 x 0.07 x 0.03), an off-centre
 *  box (0.04 x 0.05 x 0.09) on top of it and a hexagonal prism (r 0.02, h 0.05, turned by 10
 *  degrees) on top of that, merged into one mesh (three closed components, 86 vertices, 36 faces)
 *  and centred on its bounding box. Overall size about 0.10 x 0.07 x 0.17 m. */
pcl::PolygonMesh makeStatue();

/** \brief A table-top rectangle sx x sy (metres) in the z = 0 plane, centred at the origin, normal
 *  +z: 4 vertices, 1 quad. This is an open surface (not a solid). */
pcl::PolygonMesh makePlane(double sx, double sy);

/** \brief A named synthetic model with its symmetry and display colour. */
struct SyntheticModel {
  std::string name;
  pcl::PolygonMesh mesh;
  Symmetry symmetry;
  Eigen::Vector3f rgb = Eigen::Vector3f::Ones();  ///< colour, each channel in [0, 1]
};

/** \brief A model by name: "Box5", "EisKaffe", "YellowRoundSalt", "Amicelly" (the thesis models)
 *  or the distractors "Cup" and "Statue".
 *  \throws std::invalid_argument for any other name. */
SyntheticModel thesisModel(const std::string& name);

/** \brief A model of the generated suites by name: the thesis's models and distractors
 *  (thesisModel), and the shapes made for the suites: LargeBox (scenario 2's "another
 *  rectangular shaped object", 20 x 12 x 8 cm), TallCylinder (r 3.5 cm, h 16 cm, red),
 *  WideCylinder (its decoy: shorter and wider, r 5 cm, h 10 cm, red too) and OtherBox (Box5's
 *  decoy: 16 x 6 x 10 cm, Box5's blue). The decoys carry their target's colour, so colour
 *  cannot tell them apart.
 *  \throws std::invalid_argument for any other name. */
SyntheticModel suiteModel(const std::string& name);

/** \brief The four thesis models: Box5, EisKaffe, YellowRoundSalt, Amicelly. */
std::vector<std::string> thesisModelNames();

/** \brief All models known to thesisModel: the four thesis models, then Cup and Statue. */
std::vector<std::string> allModelNames();

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
