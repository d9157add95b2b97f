/***************************************************************************
  measurementwindows.cpp
 ***************************************************************************/
#include "workstation/measurementwindows.h"

#include <algorithm>
#include <stdexcept>

#include "geometry/epipolar.h"

namespace geostation
{
  MeasurementWindowSummary measurementWindows( const std::vector<MeasurementView> &views, const std::vector<cv::Size> &imageSizes, size_t reference,
      const Eigen::Vector2d &pixelInReference, const ProposalOptions &options, long long maxPixels )
  {
    if ( reference >= views.size() || !views[reference].image )
      throw std::invalid_argument( "measurementWindows: the reference view must exist and be oriented" );
    if ( imageSizes.size() != views.size() )
      throw std::invalid_argument( "measurementWindows: one image size per view is needed" );
    if ( maxPixels < 1 )
      throw std::invalid_argument( "measurementWindows: a window must be allowed at least one pixel" );
    MeasurementWindowSummary summary;
    summary.windows.resize( views.size() );
    const cv::Rect referenceWindow = matchingWindowAround( pixelInReference, 0.0, options.area, imageSizes[reference] );
    if ( !referenceWindow.empty() )
      summary.windows[reference] = referenceWindow;
    // the point predicted on the surface, where the windows are centred when they must be cut
    std::optional<Eigen::Vector3d> predicted;
    if ( options.groundOfPixel )
      predicted = options.groundOfPixel( *views[reference].image, pixelInReference );
    for ( size_t i = 0; i < views.size(); ++i )
    {
      if ( i == reference || !views[i].image )
        continue;
      const EpipolarCurve curve = epipolarCurve( *views[reference].image, pixelInReference, *views[i].image, options.epipolar );
      // the curve within the frame and the band searched beside it
      std::vector<Eigen::Vector2d> inFrame;
      for ( const auto &piece : curve.pieces )
        for ( const EpipolarVertex &v : piece )
          if ( v.inFrame )
            inFrame.push_back( v.pixelInImage );
      std::optional<Eigen::Vector2d> centre;
      if ( predicted )
        if ( const GroundProjection p = views[i].image->projectGroundToPixel( *predicted ); p.ok() )
          centre = p.pixelInImage;
      bool cut = false;
      const cv::Rect window = matchingWindowAlong( inFrame, options.area, imageSizes[i], maxPixels, centre, &cut );
      if ( window.empty() )
        continue;
      summary.windows[i] = window;
      if ( cut )
        summary.cut.push_back( i );
    }
    return summary;
  }

} // namespace geostation
