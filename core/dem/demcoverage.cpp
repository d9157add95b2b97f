/***************************************************************************
  demcoverage.cpp - how much of the ground seen in a photo the DEM covers
 ***************************************************************************/
#include "dem/demcoverage.h"

#include <cmath>
#include <stdexcept>

namespace geostation
{

  namespace
  {
    //! "the top left", "the bottom", "the middle" ... of a frame, by thirds.
    std::string partOfFrame( const Eigen::Vector2d &pixel, double width, double height )
    {
      const int column = pixel.x() < width / 3.0 ? 0 : pixel.x() > 2.0 * width / 3.0 ? 2 : 1;
      const int row = pixel.y() < height / 3.0 ? 0 : pixel.y() > 2.0 * height / 3.0 ? 2 : 1;
      static const char *const rows[] = { "top", "", "bottom" };
      static const char *const columns[] = { "left", "", "right" };
      if ( row == 1 && column == 1 )
        return "the middle";
      if ( row == 1 )
        return std::string( "the " ) + columns[column] + " side";
      if ( column == 1 )
        return std::string( "the " ) + rows[row];
      return std::string( "the " ) + rows[row] + " " + columns[column];
    }

    std::string percent( double fraction )
    {
      return std::to_string( static_cast<int>( std::floor( 100.0 * fraction ) ) ) + " %";
    }
  } // namespace

  void DemCoverageOptions::check() const
  {
    if ( columns < 2 || columns > 200 || rows < 2 || rows > 200 )
      throw std::invalid_argument( "the DEM coverage needs 2 to 200 sample columns and rows (got " + std::to_string( columns ) + " x " + std::to_string( rows ) + ")" );
  }

  DemCoverageSummary demCoverageOfImage( const Monoplotter &monoplotter, const DemCoverageOptions &options )
  {
    options.check();
    const OrientedImage &image = monoplotter.image();
    // the camera's frame; a scanned film's picture is that frame mapped into the scan (its pixels are the image's)
    const double width = image.camera().width, height = image.camera().height;
    DemCoverageSummary s;
    Eigen::Vector2d coveredSum = Eigen::Vector2d::Zero(), uncoveredSum = Eigen::Vector2d::Zero();
    Eigen::Vector2d coveredInFrame = Eigen::Vector2d::Zero(), uncoveredInFrame = Eigen::Vector2d::Zero();
    for ( int r = 0; r < options.rows; ++r )
      for ( int c = 0; c < options.columns; ++c )
      {
        const Eigen::Vector2d inFrame( ( c + 0.5 ) * width / options.columns, ( r + 0.5 ) * height / options.rows );
        const Eigen::Vector2d pixel = image.hasScanAffine() ? image.scanFromNominal( inFrame ) : inFrame;
        ++s.samples;
        const std::optional<Ray> ray = image.worldRayFromPixel( pixel );
        if ( !ray || ray->direction.z() >= 0.0 )
        {
          ++s.sky;
          continue;
        }
        const MonoplotPoint p = monoplotter.imageToGround( pixel, false );
        if ( p.ok() )
        {
          ++s.onDem;
          coveredSum += pixel;
          coveredInFrame += inFrame;
          continue;
        }
        ( p.status == DemIntersection::Status::Hole ? s.onHoles : s.offDem ) += 1;
        uncoveredSum += pixel;
        uncoveredInFrame += inFrame;
      }
    const int uncovered = s.offDem + s.onHoles;
    if ( uncovered > 0 )
    {
      s.uncoveredCentrePx = uncoveredSum / uncovered;
      uncoveredInFrame /= uncovered;
    }
    if ( s.onDem > 0 )
    {
      s.coveredCentrePx = coveredSum / s.onDem;
      coveredInFrame /= s.onDem;
    }
    const std::string rays = std::to_string( s.groundSamples() ) + " sample rays towards the ground";
    if ( s.groundSamples() == 0 )
      s.message = "no part of the photo looks down at the ground (all " + std::to_string( s.samples ) + " sample rays point at or above the horizon)";
    else if ( s.complete() )
      s.message = "the DEM covers the ground of the whole photo (" + rays + ")";
    else
    {
      const std::string holes = s.onHoles > 0 ? " (" + std::to_string( s.onHoles ) + " on holes in it)" : "";
      if ( s.onDem == 0 )
        s.message = "the DEM does not cover the ground seen in the photo: none of the " + rays + " meets it" + holes + "; nothing digitised in it can be placed on the terrain";
      else if ( 2 * s.onDem >= s.groundSamples() )
        s.message = "the DEM covers " + percent( s.coveredFraction() ) + " of the ground seen in the photo: " + std::to_string( uncovered ) + " of " + rays + " miss it" + holes + ", mostly in " +
                    partOfFrame( uncoveredInFrame, width, height ) + " of the frame; what is digitised there cannot be placed on the terrain";
      else
        s.message = "the DEM covers only " + percent( s.coveredFraction() ) + " of the ground seen in the photo, in " + partOfFrame( coveredInFrame, width, height ) + " of the frame (" +
                    std::to_string( uncovered ) + " of " + rays + " miss it" + holes + "); what is digitised elsewhere cannot be placed on the terrain";
    }
    return s;
  }

} // namespace geostation
