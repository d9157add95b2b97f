/***************************************************************************
  windowshape.h - the shape of a matching window predicted from the surface
  -------------------------------------------------------------------------
  Thesis ch. 5, "large geometric distortion": a square window in one image
  of an oblique or close-range pair shows a differently shaped patch of the
  ground in the other (the road surface seen from two stations 10 m apart
  is scaled and sheared several times over), so square windows correlate
  poorly and least squares starts far from its solution. When the images
  are oriented and the surface is known - the road plane under the van, or
  a DEM - the patch's shape in the search image follows from the geometry:
  the reference pixel's ray meets the surface, and the local mapping from
  reference pixels to search pixels through the surface is its Jacobian.
  It is computed here by central differences (rays of the neighbouring
  pixels intersected with the same surface and projected into the search
  image), so lens distortion, scanned-film affines and a curved DEM are
  all taken into account without special cases.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_WINDOWSHAPE_H
#define GEOSTATION_GEOMETRY_WINDOWSHAPE_H

#include <functional>
#include <optional>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  //! The ground point of a pixel of an image (road plane or DEM, block CRS metres); nothing where the ray misses.
  using GroundOfPixel = std::function<std::optional<Eigen::Vector3d>( const OrientedImage &, const Eigen::Vector2d & )>;

  //! Ray / horizontal plane Z = heightM; nothing behind the camera or for rays nearly parallel to it.
  std::optional<Eigen::Vector3d> roadPlanePoint( const OrientedImage &image, const Eigen::Vector2d &pixelInImage, double heightM );

  struct PredictedWindow
  {
    Eigen::Vector3d groundPoint = Eigen::Vector3d::Zero();   //!< the reference pixel on the surface, block CRS metres
    Eigen::Vector2d pixelInSearch = Eigen::Vector2d::Zero(); //!< where that surface point appears in the search image
    /**
     * d(search pixel) / d(reference pixel) through the surface: column k is
     * the search-image offset of a one-pixel step along reference column
     * (k = 0) or row (k = 1). The starting shape of least-squares matching
     * ([a1 a2; b1 b2] of eq. 5.9).
     */
    Eigen::Matrix2d searchFromReference = Eigen::Matrix2d::Identity();
  };

  /**
   * The window of `pixelInReference` as it appears in `search` if the
   * point lies on the surface that `groundOfPixel` describes. `stepPx` is
   * the half-width of the central differences (reference pixels; about a
   * quarter of the window suits a curved surface). Nothing when the ray or
   * a neighbouring ray misses the surface, the point does not project into
   * the search image (behind it, or outside the lens field) or the mapping
   * is degenerate (the surface seen edge-on). Throws std::invalid_argument
   * if stepPx <= 0.
   */
  std::optional<PredictedWindow> predictWindowShape( const OrientedImage &reference, const Eigen::Vector2d &pixelInReference, const OrientedImage &search,
      const GroundOfPixel &groundOfPixel, double stepPx = 2.0 );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_WINDOWSHAPE_H
