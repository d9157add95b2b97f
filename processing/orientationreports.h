/***************************************************************************
  orientationreports.h - the HTML reports of the orienting algorithms
  -------------------------------------------------------------------------
  bundle_adjust, resection, inner_orientation and identify_control write,
  on request (REPORT_HTML), a page a person reads beside their JSON
  REPORT: the summary, the parameters with their standard deviations,
  residual tables per image and per point, the residual vectors drawn over
  the image frame and a histogram of the residuals. Residuals are in the
  sense of the JSON reports: projected (or transformed) minus measured.
 ***************************************************************************/
#ifndef ORIENTATIONREPORTS_H
#define ORIENTATIONREPORTS_H

#include <map>
#include <string>
#include <vector>

#include <QByteArray>
#include <QString>

#include "adjustment/bundleadjustment.h"
#include "adjustment/innerorientation.h"
#include "adjustment/resection.h"
#include "identification/photoidentification.h"
#include "io/block.h"

namespace GeoStationProcessing
{
  /**
   * Bundle adjustment: summary, images (RMS, orientation with sigmas,
   * shift), freed interior parameters, control and check points, the
   * points with the largest RMS (tie points too) and the largest
   * residuals, a residual plot for each of the images with the
   * largest RMS (at most 12) and the histogram of all residuals.
   */
  QByteArray bundleAdjustHtml( const geostation::BundleSummary &s, const geostation::Block &block );

  //! Resection of one image; `measured` holds the image point of every point id (pixels, as adjusted).
  QByteArray resectionHtml( const geostation::ResectionSummary &s, const QString &imageId, const geostation::Camera &camera,
                            const std::map<std::string, Eigen::Vector2d> &measured );

  //! Inner orientation of one scanned photo from its `measured` fiducials (scan pixels).
  QByteArray innerOrientationHtml( const geostation::InnerOrientationSummary &s, const QString &imageId, const QString &cameraId,
                                   const std::vector<geostation::FiducialMeasurement> &measured );

  //! Control identified in one photo of `frameWidth` x `frameHeight` file pixels.
  QByteArray identifyControlHtml( const geostation::PhotoIdentificationSummary &s, const QString &imageId, int frameWidth, int frameHeight );

} // namespace GeoStationProcessing

#endif // ORIENTATIONREPORTS_H
