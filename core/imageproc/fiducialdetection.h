/***************************************************************************
  fiducialdetection.h - automatic location of fiducial marks in a scan
  -------------------------------------------------------------------------
  Stokes' (1988) procedure (Stokes 1988, §4): one fiducial mark in
  each corner window of the scan; each window is read subsampled so the
  marks have the same size whatever the scan resolution, filtered with a
  template of the mark (normalised cross-correlation), and the best match is
  then refined by a centre of gravity at full resolution.
 ***************************************************************************/
#ifndef GEOSTATION_IMAGEPROC_FIDUCIALDETECTION_H
#define GEOSTATION_IMAGEPROC_FIDUCIALDETECTION_H

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "camera/camera.h"
#include "progress/progress.h"

namespace geostation
{

  struct FiducialDetectionOptions
  {
    double scanPixelMm = 0.0;      //!< scan resolution; sets the window (51.2 mm) and subsampling (to 0.1 mm)
    cv::Mat markTemplate;          //!< the mark at full resolution (8-bit grey); empty: a generic disc
    double markDiameterPx = 30.0;  //!< generic disc, at full resolution
    bool brightMark = true;        //!< generic disc: bright on dark (false: dark on bright)
    double minScore = 0.5;         //!< normalised correlation below this: not found
    Progress progress;             //!< told before each corner and asked whether to stop (the corners left: Status::Cancelled)
  };

  enum class Corner
  {
    TopLeft,
    TopRight,
    BottomRight,
    BottomLeft
  };

  struct DetectedFiducial
  {
    enum class Status
    {
      Found,
      WindowTooSmall, //!< the corner window is smaller than the mark
      NoMark,         //!< the best correlation in the window is below the threshold
      NoContrast,     //!< the mark has no contrast against its background (no centre of gravity)
      Cancelled,      //!< not looked for: the caller asked to stop (FiducialDetectionOptions::progress)
    };
    Corner corner = Corner::TopLeft;
    Status status = Status::NoMark;
    std::string message;       //!< why not found
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double score = 0.0;        //!< normalised cross-correlation of the match

    bool found() const { return status == Status::Found; }
  };

  /**
   * Finds one mark in each corner window of an image file (any GDAL raster;
   * band 1; only the windows are read). Throws std::runtime_error if the file
   * cannot be read and std::invalid_argument for bad options.
   */
  std::array<DetectedFiducial, 4> detectCornerFiducials( const std::string &imagePath, const FiducialDetectionOptions &options );

  /**
   * The camera's fiducial for each corner: the one farthest from the centre
   * in that quadrant of the photo (x right, y up). Empty id if none.
   */
  std::array<std::string, 4> cornerFiducialIds( const std::vector<Fiducial> &fiducials );

} // namespace geostation

#endif // GEOSTATION_IMAGEPROC_FIDUCIALDETECTION_H
