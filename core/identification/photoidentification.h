/***************************************************************************
  photoidentification.h - control identified in a photo file, end to end
  -------------------------------------------------------------------------
  What geostation:identify_control and the orientation dock's "Identify"
  share: the marks of the photo's file (scan pixels for a scanned film)
  detected and taken into the camera's nominal frame, the distance-list
  identification (controlidentification.h), and each identified mark
  located again at its prediction from the identified orientation (the
  semi-automatic step, controlprediction.h), keeping that centre where the
  two agree. Pixels in and out are the file's.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H
#define GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "identification/controlidentification.h"
#include "identification/controlprediction.h"
#include "identification/markcandidates.h"

namespace geostation
{

  struct PhotoIdentificationOptions
  {
    MarkCandidateOptions marks;
    ControlIdentificationOptions identification;
    //! The second pass's centre is kept where it is within this of the identified mark's (pixels).
    double agreementPx = 1.5;
    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! One identified control point, in the file's pixels.
  struct PhotoIdentifiedPoint
  {
    std::string pointId;
    Eigen::Vector2d pixelInFile = Eigen::Vector2d::Zero();
    Eigen::Vector2d predictedInFile = Eigen::Vector2d::Zero(); //!< by the identified orientation
    double sigmaPx = 0.5;
    bool relocated = false;  //!< the centre of the second pass (else the detected mark's)
  };

  struct PhotoIdentificationSummary
  {
    ControlIdentificationSummary identification; //!< the search, its status and message, the resection
    std::vector<PhotoIdentifiedPoint> identified;
    std::vector<std::pair<std::string, Eigen::Vector2d>> notFound; //!< predicted in the photo (file pixels), no mark paired
    int candidates = 0;
    int relocated = 0;
    bool ok() const { return identification.ok(); }
  };

  /**
   * Identifies `control` in the photo `greyFile` (8-bit grey, the file's
   * pixels; markGrey()). `nominalFromFile` is a scanned film's scan affine.
   * Throws like identifyControl().
   */
  PhotoIdentificationSummary identifyControlInPhoto( const cv::Mat &greyFile, const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const std::vector<ControlPoint> &control, const PhotoIdentificationOptions &options = PhotoIdentificationOptions() );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_PHOTOIDENTIFICATION_H
