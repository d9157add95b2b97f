/***************************************************************************
  roadnetworkextractor.cpp - a road network from a stereo pair, end to end
 ***************************************************************************/
#include "extraction/roadnetworkextractor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "adjustment/intersection.h"
#include "extraction/greytiles.h"
#include "geometry/epipolar.h"
#include "matching/areamatcher.h"
#include "matching/matchingwindows.h"

namespace geostation
{

  double verificationSearchPx( const RegistrationReport &registration, double ceilingPx )
  {
    if ( !std::isfinite( registration.expectedPx ) )
      return ceilingPx;
    return std::clamp( 2.0 * registration.expectedPx + 2.0, std::min( 3.0, ceilingPx ), ceilingPx );
  }

  RoadWidthsPx widthsPxFor( const OrientedImage &a, double heightM, const std::pair<double, double> &widthM )
  {
    if ( !( widthM.first > 0.0 ) || !( widthM.second >= widthM.first ) || !std::isfinite( widthM.second ) )
      throw std::invalid_argument( "the road widths in metres must satisfy 0 < narrowest <= widest" );
    // the ground pixel: two neighbouring pixels at the image's centre carried to the terrain height
    const Eigen::Vector2d centre( 0.5 * a.camera().width, 0.5 * a.camera().height );
    const auto ground = [&]( const Eigen::Vector2d &p ) -> std::optional<Eigen::Vector3d> {
      const std::optional<Ray> ray = a.worldRayFromPixel( p );
      if ( !ray || std::abs( ray->direction.z() ) < 1e-9 )
        return std::nullopt;
      const double t = ( heightM - ray->origin.z() ) / ray->direction.z();
      return t > 0.0 ? std::optional<Eigen::Vector3d>( ray->origin + t * ray->direction ) : std::nullopt;
    };
    const std::optional<Eigen::Vector3d> p0 = ground( centre ), px = ground( centre + Eigen::Vector2d( 1.0, 0.0 ) ), py = ground( centre + Eigen::Vector2d( 0.0, 1.0 ) );
    if ( !p0 || !px || !py )
      throw std::invalid_argument( "the first image's centre does not see the ground at the terrain height: give the road widths in pixels" );
    RoadWidthsPx w;
    w.groundPixelM = std::sqrt( ( *px - *p0 ).norm() * ( *py - *p0 ).norm() );
    const double minPx = widthM.first / w.groundPixelM, maxPx = widthM.second / w.groundPixelM;
    w.minPx = std::clamp( minPx, 1.0, kMaxRoadWidthPx );
    w.maxPx = std::clamp( maxPx, w.minPx, kMaxRoadWidthPx );
    w.clamped = minPx < 1.0 || maxPx > kMaxRoadWidthPx;
    return w;
  }

  RoadNetworkOptions defaultRoadNetworkOptions()
  {
    RoadNetworkOptions options;
    options.coincident.extraction.object.polarity = 0;
    options.roadWidthM = std::make_pair( 3.0, 30.0 );
    options.contrastPerTexture = 1.8;
    return options;
  }

  double textureGrey( const GreyTiles &grey )
  {
    constexpr int kPatches = 9, kPatch = 64, kWindow = 7, kSpacing = 16;
    std::vector<double> deviations;
    for ( int i = 0; i < kPatches; ++i )
      for ( int j = 0; j < kPatches; ++j )
      {
        const cv::Rect patch( ( grey.width() - kPatch ) * ( j + 0.5 ) / kPatches, ( grey.height() - kPatch ) * ( i + 0.5 ) / kPatches, kPatch, kPatch );
        const cv::Rect inside = patch & cv::Rect( 0, 0, grey.width(), grey.height() );
        if ( inside.width < kWindow || inside.height < kWindow )
          continue;
        const GreyWindow window = grey.window( inside );
        for ( int r = 0; r + kWindow <= window.pixels.rows; r += kSpacing )
          for ( int c = 0; c + kWindow <= window.pixels.cols; c += kSpacing )
          {
            cv::Scalar mean, deviation;
            cv::meanStdDev( window.pixels( cv::Rect( c, r, kWindow, kWindow ) ), mean, deviation );
            deviations.push_back( deviation[0] );
          }
      }
    if ( deviations.empty() )
      return 0.0;
    std::nth_element( deviations.begin(), deviations.begin() + deviations.size() / 2, deviations.end() );
    return deviations[deviations.size() / 2];
  }

  RoadNetworkSummary extractRoadNetwork( const MatchImage &imageA, const MatchImage &imageB, const OrientedImage *a, const OrientedImage *b,
                                         const RoadNetworkOptions &options, const Progress &progress )
  {
    if ( imageA.empty() || imageB.empty() )
      throw std::invalid_argument( "both images of the pair are needed" );
    if ( imageA.windowed() || imageB.windowed() )
      throw std::invalid_argument( "road extraction needs the whole images, not windows of them" );
    PairMatchWindows matching( imageA, imageB );
    return extractRoadNetwork( GreyTiles( imageA.grey() ), GreyTiles( imageB.grey() ), matching, a, b, options, progress );
  }

  RoadNetworkSummary extractRoadNetwork( const GreyTiles &greyA, const GreyTiles &greyB, PairMatchWindows &matching, const OrientedImage *a, const OrientedImage *b,
                                         const RoadNetworkOptions &options, const Progress &progress )
  {
    const auto start = std::chrono::steady_clock::now();
    if ( greyA.size() != matching.size( 0 ) || greyB.size() != matching.size( 1 ) )
      throw std::invalid_argument( "the grey images and the matching images of the pair must have the same sizes" );
    if ( ( a == nullptr ) != ( b == nullptr ) )
      throw std::invalid_argument( "either both images of the pair are oriented or neither" );
    options.coincident.check();
    RoadNetworkSummary summary;
    summary.oriented = a != nullptr;
    std::unique_ptr<PairMapping> mapping;
    if ( !options.control.empty() || !summary.oriented )
    {
      if ( options.control.empty() )
        throw std::invalid_argument( "an unoriented pair needs a table of control-point pairs for its registration" );
      RegistrationReport report;
      if ( options.controlMapping == ControlMapping::Projective )
        mapping = std::make_unique<ProjectiveMapping>( ProjectiveMapping::fit( options.control, &report ) );
      else
        mapping = std::make_unique<MultiquadricMapping>( MultiquadricMapping::fit( options.control, 1.0, &report ) );
      summary.registration = report;
    }
    if ( !progress.report( 0.0, "the pair's set-up" ) )
    {
      summary.extraction.cancelled = true;
      return summary;
    }
    if ( summary.oriented )
    {
      if ( options.meanHeightM )
        summary.meanHeightM = *options.meanHeightM;
      else
      {
        const TerrainHeightEstimate estimate = estimateTerrainHeight( *a, *b, matching );
        if ( estimate.ok() )
          summary.terrainEstimate = estimate;
        else if ( !options.terrain )
          throw std::invalid_argument( "the terrain height could not be estimated by matching: " + estimate.message + "; give a DEM or a mean terrain height" );
        summary.meanHeightM = summary.terrainEstimate ? summary.terrainEstimate->heightM : 0.0;
      }
    }
    std::optional<OrientedPairMapping> oriented;
    if ( summary.oriented )
    {
      oriented.emplace( *a, *b, summary.meanHeightM, options.terrain );
      // a 9 x 9 grid of the first image mapped into the second: none inside, no stereo model
      bool overlap = false;
      for ( int r = 0; r <= 8 && !overlap; ++r )
        for ( int c = 0; c <= 8 && !overlap; ++c )
          if ( const std::optional<Eigen::Vector2d> q = oriented->toB( Eigen::Vector2d( greyA.width() * c / 8.0, greyA.height() * r / 8.0 ) ) )
            overlap = q->x() >= 0 && q->y() >= 0 && q->x() <= greyB.width() && q->y() <= greyB.height();
      if ( !overlap )
        throw std::invalid_argument( "the two images do not overlap (at the terrain height of " + std::to_string( static_cast<int>( std::lround( summary.meanHeightM ) ) ) + " m): no stereo pair" );
    }
    const PairMapping &registration = mapping ? *mapping : static_cast<const PairMapping &>( *oriented );
    summary.mapping = registration.name();
    CoincidentExtractionOptions coincident = options.coincident;
    if ( options.roadWidthM && summary.oriented )
    {
      summary.widthsFromMetres = widthsPxFor( *a, summary.meanHeightM, *options.roadWidthM );
      coincident.extraction.object.minWidthPx = summary.widthsFromMetres->minPx;
      coincident.extraction.object.maxWidthPx = summary.widthsFromMetres->maxPx;
      coincident.check();
    }
    if ( options.contrastPerTexture > 0.0 )
    {
      summary.textureGrey = textureGrey( greyA );
      coincident.extraction.object.minContrast = std::max( coincident.extraction.object.minContrast, options.contrastPerTexture * summary.textureGrey );
    }
    summary.minContrast = coincident.extraction.object.minContrast;
    if ( summary.registration )
      coincident.verification.misregistrationPx = verificationSearchPx( *summary.registration, coincident.verification.misregistrationPx );
    summary.verificationSearchPx = coincident.verification.misregistrationPx;
    if ( !options.extract )
    {
      summary.seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - start ).count();
      return summary;
    }
    // the extraction most of the time; the 3-D lines from 90 %
    summary.extraction = extractCoincident( greyA, greyB, registration, coincident, progress.part( 0.02, oriented ? 0.9 : 1.0 ) );
    if ( oriented && !summary.extraction.cancelled )
    {
      if ( progress.report( 0.9, "the 3-D lines" ) )
        summary.network = intersectNetwork( *oriented, summary.extraction.linesA, summary.extraction.linesB, matching, options.network );
      else
        summary.extraction.cancelled = true;
    }
    summary.reading.inWindows = !greyA.whole() || !greyB.whole();
    summary.reading.greyTilesRead = greyA.tilesRead() + greyB.tilesRead();
    summary.reading.matchingWindows = matching.windowsRead();
    summary.reading.peakMatchingBytes = matching.peakBytes();
    summary.seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - start ).count();
    return summary;
  }

  RoadNetworkSummary extractRoadNetwork( std::shared_ptr<const RasterReader> readerA, std::shared_ptr<const RasterReader> readerB, const OrientedImage *a,
                                         const OrientedImage *b, const RoadNetworkOptions &options, const Progress &progress )
  {
    using Range = std::optional<std::pair<double, double>>;
    const auto range = []( const RasterReader &r ) { return r.eightBit() ? Range() : Range( greyRangeOf( r ) ); };
    const Range rangeA = range( *readerA ), rangeB = range( *readerB );
    PairMatchWindows matching( matchWindowsOf( readerA, readerB, rangeA, rangeB ), readerA->size(), readerB->size() );
    return extractRoadNetwork( greyTilesOf( readerA, rangeA ), greyTilesOf( readerB, rangeB ), matching, a, b, options, progress );
  }

} // namespace geostation
