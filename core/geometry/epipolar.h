/***************************************************************************
  epipolar.h - epipolar curves between two oriented images
  -------------------------------------------------------------------------
  For a pixel in one image, the points of its ray between two distances
  project into the other image along the epipolar line; with lens distortion
  that line is a curve. It is returned as a polyline densified so that no
  segment is longer than a given number of pixels (thesis §3.2, eq. 3.11).
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_EPIPOLAR_H
#define GEOSTATION_GEOMETRY_EPIPOLAR_H

#include <vector>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  struct EpipolarOptions
  {
    double minDistanceM = 2.0;  //!< along the ray from the first image's projection centre
    double maxDistanceM = 50.0;
    double maxSegmentPx = 2.0;  //!< densify until consecutive vertices are this close (near the frame)
    int maxVertices = 20000;    //!< safety bound on densification
  };

  struct EpipolarVertex
  {
    Eigen::Vector2d pixelInImage; //!< in the second image
    double distanceM;             //!< along the ray in the first image
    bool inFrame;
  };

  struct EpipolarCurve
  {
    /**
     * Continuous pieces of the curve, each ordered by increasing distance. The
     * curve breaks where the ray passes behind the second camera or out of
     * its lens field. Empty when the pixel's ray is undefined or nothing of
     * the distance range projects.
     */
    std::vector<std::vector<EpipolarVertex>> pieces;

    //! Total number of vertices.
    size_t vertexCount() const;

    /**
     * Distance in pixels from a pixel to the nearest point of the curve, and
     * the ray distance there (linear along the segment); infinity if empty.
     */
    double distanceToCurvePx( const Eigen::Vector2d &pixelInImage, double *distanceAlongRayM = nullptr ) const;
  };

  /**
   * The epipolar curve in image `to` of pixel `pixelInFrom` in image `from`.
   * The reverse curve is epipolarCurve(to, pixel, from). Throws
   * std::invalid_argument unless 0 < minDistanceM < maxDistanceM and
   * maxSegmentPx > 0.
   */
  EpipolarCurve epipolarCurve( const OrientedImage &from, const Eigen::Vector2d &pixelInFrom, const OrientedImage &to, const EpipolarOptions &options = EpipolarOptions() );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_EPIPOLAR_H
