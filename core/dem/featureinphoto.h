/***************************************************************************
  featureinphoto.h - a map feature drawn into an oriented photo
  -------------------------------------------------------------------------
  The one rule for putting a map feature (points, lines, rings in the
  block CRS) into a photo, used by project_to_image, the Multiview's
  overlay of measured features and the orientation dock's layer in the
  photo (Stokes (1988)'s map-to-image direction):

  - heights, in the order the call states (FeatureHeights): the vertex's
    own Z, the DEM's height, a plane; a vertex none of them gives a height
    is refused with a status, and the rest of the layer goes on;
  - a line is densified so it follows its curve in the photo; the points
    inserted take their heights from the DEM when every vertex of the part
    took its height from it, else by linear interpolation;
  - a line is cut where it leaves the space the photo can show, at the
    boundary found by bisection; a ring is clipped to it in 3-D
    (geometry/lineprojection);
  - with a DEM the terrain hides points; asked, lines are split into runs
    that are wholly seen or wholly hidden.

  Pixels are (col, row) as docs/conventions.md §1; geometry/imagespace.h
  turns them into QGIS's image space (x = col, y = -row).
 ***************************************************************************/
#ifndef GEOSTATION_DEM_FEATUREINPHOTO_H
#define GEOSTATION_DEM_FEATUREINPHOTO_H

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "dem/monoplotter.h"
#include "geometry/lineprojection.h"

namespace geostation
{

  /**
   * Where a vertex's height comes from, tried in this order: its own Z
   * (when `featureZ` and the Z is finite), the DEM (`dem`, which also hides
   * what the terrain hides), the plane Z = `planeZ`.
   */
  struct FeatureHeights
  {
    bool featureZ = true;
    const Monoplotter *dem = nullptr; //!< must outlive the call; null: no DEM
    std::optional<double> planeZ;
  };

  enum class FeatureHeightStatus
  {
    Ok,
    NoHeight,   //!< a vertex without Z, and neither a DEM nor a plane to give it one
    OutsideDem, //!< a vertex without Z outside the DEM, and no plane
  };

  //! One part of a feature (a point, a line, a ring) on the ground, its heights given by the rule.
  struct GroundPart
  {
    std::vector<Eigen::Vector3d> vertices;
    bool draped = false;                          //!< every vertex's height came from the DEM
    FeatureHeightStatus status = FeatureHeightStatus::Ok;
    size_t failedVertex = 0;                      //!< the first vertex without a height (status not Ok)
  };

  /**
   * The vertices (block CRS; Z NaN where a vertex has none) with their
   * heights from `heights`. On a vertex that gets no height the status
   * says why and `vertices` is empty.
   */
  GroundPart groundPart( const std::vector<Eigen::Vector3d> &vertices, const FeatureHeights &heights );

  //! A ground point in the photo: its projection, and whether the terrain (the DEM, when given) leaves it visible.
  GroundPointView pointInPhoto( const OrientedImage &image, const Eigen::Vector3d &ground, const FeatureHeights &heights );

  struct LineInPhotoOptions
  {
    double densifyPx = 2.0;   //!< longest projected piece, pixels
    bool closed = false;      //!< a ring: clipped in 3-D to the photo's field instead of cut
    bool splitHidden = false; //!< runs split where the terrain starts or stops hiding the line (a ring is then cut as a line)
  };

  /**
   * A part of two or more vertices (from groundPart()) in the photo.
   * Throws std::invalid_argument if the part's status is not Ok or
   * options.densifyPx <= 0.
   */
  ProjectedGroundLine lineInPhoto( const OrientedImage &image, const GroundPart &part, const FeatureHeights &heights, const LineInPhotoOptions &options );

} // namespace geostation

#endif // GEOSTATION_DEM_FEATUREINPHOTO_H
