/***************************************************************************
  monoplotter.h - one oriented image and a DEM: image <-> map
  -------------------------------------------------------------------------
  Stokes' (1988) job: a pixel's ray meets the terrain (image -> map,
  with precision from the pixel, DEM and exterior-orientation sigmas), and a
  map point is projected into the image with a test whether the terrain
  hides it (map -> image). Lines are densified so a straight segment in the
  photo drapes over the terrain and a straight map segment curves in the
  photo.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_MONOPLOTTER_H
#define GEOSTATION_DEM_MONOPLOTTER_H

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dem/demintersection.h"
#include "geometry/lineprojection.h"
#include "geometry/projection.h"

namespace geostation
{

  struct MonoplotOptions
  {
    DemIntersectionOptions intersection;
    double pixelSigmaPx = 0.5;       //!< measurement precision in the image
    double demSigmaM = 0.0;          //!< height precision of the DEM
    bool propagateExterior = true;   //!< include the image's exterior sigmas, if it has them
  };

  struct MonoplotPoint
  {
    DemIntersection::Status status = DemIntersection::Status::Miss;
    std::string message;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    Eigen::Vector3d world = Eigen::Vector3d::Zero(); //!< block CRS
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    double rangeM = 0.0;
    //! Height sigma of bridged DEM cells under the point (DemOptions::bridgeHolesUpToCells), in the precision; 0: none.
    double bridgeSigmaM = 0.0;

    bool ok() const { return status == DemIntersection::Status::Hit; }
    bool onBridgedCells() const { return bridgeSigmaM > 0.0; }
  };

  struct MapPointInImage
  {
    GroundProjection projection;
    bool visible = false; //!< projected, in the frame, and not hidden by the terrain
  };

  /**
   * The runs of consecutive resolved points of a monoplotted line (index
   * ranges [first, last] of at least two points), the longest on the ground
   * first: what of a line that meets a DEM hole or the horizon part-way can
   * be kept. Empty if no two consecutive points are resolved.
   */
  std::vector<std::pair<size_t, size_t>> resolvedRuns( const std::vector<MonoplotPoint> &line );

  class Monoplotter
  {
    public:
      //! The image, DEM and transform are referenced, not copied: keep them alive.
      Monoplotter( const OrientedImage &image, const Dem &dem, const CrsTransform &blockToDem, const MonoplotOptions &options = MonoplotOptions() );

      //! The ground point of a pixel; with `precision`, its covariance too.
      MonoplotPoint imageToGround( const Eigen::Vector2d &pixelInImage, bool precision = true ) const;

      /**
       * A map point in the image; `visible` also tests whether the terrain
       * hides it (its ray meets the DEM well before the point).
       */
      MapPointInImage groundToImage( const Eigen::Vector3d &pointInWorld ) const;

      /**
       * An image polyline on the ground: every segment is densified so that
       * consecutive pixels are at most `densifyPx` apart, then monoplotted.
       */
      std::vector<MonoplotPoint> imageLineToGround( const std::vector<Eigen::Vector2d> &vertices, double densifyPx, bool precision = true ) const;

      /**
       * A map polyline (block CRS, with heights) in the image: segments are
       * split until their projections are at most `densifyPx` long. With
       * `drape`, the heights of the inserted points come from the DEM
       * (vertices keep theirs); otherwise they are interpolated linearly.
       */
      std::vector<MapPointInImage> groundLineToImage( const std::vector<Eigen::Vector3d> &vertices, double densifyPx, bool drape ) const;

      //! The DEM height under a block-CRS point, or nothing.
      std::optional<double> demHeightAt( const Eigen::Vector3d &pointInWorld ) const;

      //! The oriented image it monoplots.
      const OrientedImage &image() const { return mImage; }

    private:
      std::optional<Eigen::Vector3d> hit( const OrientedImage &image, const Eigen::Vector2d &pixel, double demShiftM, DemIntersection *out = nullptr ) const;

      const OrientedImage &mImage;
      const Dem &mDem;
      const CrsTransform &mBlockToDem;
      MonoplotOptions mOptions;
  };

  /**
   * How map features are seen from an image: through the terrain's
   * occlusion test when a monoplotter is given (`monoplotter` must outlive
   * the viewer), by plain collinearity (always visible) when it is null.
   */
  GroundPointViewer featureViewer( const OrientedImage &image, const Monoplotter *monoplotter );

} // namespace geostation

#endif // GEOSTATION_DEM_MONOPLOTTER_H
