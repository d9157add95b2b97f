/***************************************************************************
  scenebuilder.cpp - terrain, roads, objects and targets of a simulated survey
 ***************************************************************************/
#include "simulation/scenebuilder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include <cpl_conv.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "geometry/rotation.h"
#include "simulation/proceduralnoise.h"

namespace geostation
{
  namespace
  {
    constexpr double kSiteX = 500000.0, kSiteY = 4400000.0; //!< procedural sites: UTM 17N
    constexpr const char *kProceduralCrs = "EPSG:32617";

    double smoothstep( double edge0, double edge1, double x )
    {
      const double t = std::clamp( ( x - edge0 ) / ( edge1 - edge0 ), 0.0, 1.0 );
      return t * t * ( 3 - 2 * t );
    }

    std::string fmt( double v )
    {
      std::ostringstream s;
      s.precision( 10 );
      s << v;
      return s.str();
    }

    //! Arc of radius r turning by `turnRad` (positive left) from `start` heading `heading`, 2 m vertices.
    void appendArc( std::vector<Eigen::Vector2d> &line, double &heading, double radius, double turnRad )
    {
      const Eigen::Vector2d start = line.back();
      const double side = turnRad > 0 ? 1.0 : -1.0;
      const Eigen::Vector2d centre = start + side * radius * Eigen::Vector2d( -std::sin( heading ), std::cos( heading ) );
      const int n = std::max( 2, static_cast<int>( std::abs( turnRad ) * radius / 2.0 ) );
      const double a0 = heading - side * kPi / 2;
      for ( int k = 1; k <= n; ++k )
      {
        const double a = a0 + turnRad * k / n;
        line.push_back( centre + radius * Eigen::Vector2d( std::cos( a ), std::sin( a ) ) );
      }
      heading += turnRad;
    }

    void appendStraight( std::vector<Eigen::Vector2d> &line, double heading, double length )
    {
      line.push_back( line.back() + length * Eigen::Vector2d( std::cos( heading ), std::sin( heading ) ) );
    }

    //! Procedural roads around the site centre (block CRS).
    std::vector<Road> proceduralRoads( SurveyPreset preset, const Eigen::Vector2d &centre )
    {
      std::vector<Road> roads;
      Road main;
      main.id = "R1";
      Road side;
      side.id = "R2";
      side.dashedCentre = true;
      side.laneWidthM = 3.25;
      double heading = 0.0;
      switch ( preset )
      {
        case SurveyPreset::Highway:
        {
          main.lanesPerDirection = 2;
          main.laneWidthM = 3.5;
          main.centreline = { centre + Eigen::Vector2d( -60, 0 ) };
          appendStraight( main.centreline, heading, 160 );
          appendArc( main.centreline, heading, 220, degToRad( 30 ) );
          appendStraight( main.centreline, heading, 200 );
          appendArc( main.centreline, heading, 300, degToRad( -20 ) );
          appendStraight( main.centreline, heading, 400 );
          side.centreline = { centre + Eigen::Vector2d( 45, 0 ), centre + Eigen::Vector2d( 45, 260 ) };
          break;
        }
        case SurveyPreset::AerialStereo:
        case SurveyPreset::ObliquePhoto:
        {
          main.lanesPerDirection = 1;
          main.centreline = { centre + Eigen::Vector2d( -700, -40 ) };
          appendStraight( main.centreline, heading, 620 );
          appendArc( main.centreline, heading, 160, degToRad( 25 ) );
          appendStraight( main.centreline, heading, 120 );
          appendArc( main.centreline, heading, 160, degToRad( -25 ) );
          appendStraight( main.centreline, heading, 700 );
          side.centreline = { centre + Eigen::Vector2d( -20, -28 ), centre + Eigen::Vector2d( -20, -700 ) };
          Road third;
          third.id = "R3";
          third.dashedCentre = true;
          third.laneWidthM = 3.0;
          double h3 = kPi / 2;
          // leaves the main road northwards and bends
          third.centreline = { centre + Eigen::Vector2d( 40, 0 ) };
          appendStraight( third.centreline, h3, 90 );
          appendArc( third.centreline, h3, 120, degToRad( -40 ) );
          appendStraight( third.centreline, h3, 600 );
          roads.push_back( main );
          roads.push_back( side );
          roads.push_back( third );
          return roads;
        }
      }
      roads.push_back( main );
      roads.push_back( side );
      return roads;
    }

    struct OgrDataSourceCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };

    //! Line features of an OGR layer as roads in the block CRS.
    std::vector<Road> loadRoads( const std::string &path, const std::string &blockCrs, std::vector<std::string> &notes )
    {
      GDALAllRegister();
      // "file|layername=name" picks a layer; otherwise the first
      std::string file = path, layerName;
      if ( const size_t bar = path.find( '|' ); bar != std::string::npos )
      {
        file = path.substr( 0, bar );
        const size_t key = path.find( "layername=", bar );
        if ( key != std::string::npos )
          layerName = path.substr( key + 10, path.find( '|', key ) - key - 10 );
      }
      std::unique_ptr<void, OgrDataSourceCloser> ds( GDALOpenEx( file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr ) );
      if ( !ds )
        throw std::invalid_argument( "the road layer " + path + " cannot be opened as a vector layer" );
      OGRLayerH layer = layerName.empty() ? GDALDatasetGetLayer( ds.get(), 0 ) : GDALDatasetGetLayerByName( ds.get(), layerName.c_str() );
      if ( !layer )
        throw std::invalid_argument( "the road layer " + path + " has no layer" );
      OGRSpatialReferenceH srs = OGR_L_GetSpatialRef( layer );
      // a GeoPackage layer without a CRS reports an "Undefined geographic/Cartesian SRS"
      if ( srs && OSRGetName( srs ) && std::string( OSRGetName( srs ) ).rfind( "Undefined", 0 ) == 0 )
        srs = nullptr;
      if ( !srs )
        throw std::invalid_argument( "the road layer " + path + " has no CRS; set one (e.g. with ogr2ogr -a_srs) so it can be placed" );
      char *wkt = nullptr;
      OSRExportToWkt( srs, &wkt );
      const std::string layerCrs = wkt ? wkt : "";
      CPLFree( wkt );
      CrsTransform toBlock( layerCrs, blockCrs );
      if ( !toBlock.isIdentity() )
        notes.push_back( "roads reprojected from " + describeCrs( layerCrs ).name + " to the block CRS" );
      const int idField = OGR_FD_GetFieldIndex( OGR_L_GetLayerDefn( layer ), "id" );
      const int lanesField = OGR_FD_GetFieldIndex( OGR_L_GetLayerDefn( layer ), "lanes" );
      std::vector<Road> roads;
      OGR_L_ResetReading( layer );
      while ( OGRFeatureH feature = OGR_L_GetNextFeature( layer ) )
      {
        OGRGeometryH geometry = OGR_F_GetGeometryRef( feature );
        std::vector<OGRGeometryH> parts;
        if ( geometry && wkbFlatten( OGR_G_GetGeometryType( geometry ) ) == wkbLineString )
          parts.push_back( geometry );
        else if ( geometry && wkbFlatten( OGR_G_GetGeometryType( geometry ) ) == wkbMultiLineString )
          for ( int k = 0; k < OGR_G_GetGeometryCount( geometry ); ++k )
            parts.push_back( OGR_G_GetGeometryRef( geometry, k ) );
        for ( size_t k = 0; k < parts.size(); ++k )
        {
          Road road;
          const std::string base = idField >= 0 && OGR_F_IsFieldSetAndNotNull( feature, idField ) ? OGR_F_GetFieldAsString( feature, idField )
                                   : "R" + std::to_string( OGR_F_GetFID( feature ) );
          road.id = parts.size() > 1 ? base + "_" + std::to_string( k + 1 ) : base;
          if ( lanesField >= 0 && OGR_F_IsFieldSetAndNotNull( feature, lanesField ) )
            road.lanesPerDirection = std::clamp( OGR_F_GetFieldAsInteger( feature, lanesField ), 1, 4 );
          for ( int v = 0; v < OGR_G_GetPointCount( parts[k] ); ++v )
          {
            const double x = OGR_G_GetX( parts[k], v ), y = OGR_G_GetY( parts[k], v );
            const Eigen::Vector3d p = toBlock.transform( Eigen::Vector3d( x, y, 0.0 ) );
            if ( !std::isfinite( p.x() ) || !std::isfinite( p.y() ) )
              throw std::invalid_argument( "vertex " + fmt( x ) + ", " + fmt( y ) + " of road " + road.id + " cannot be transformed to the block CRS" );
            if ( road.centreline.empty() || ( road.centreline.back() - p.head<2>() ).norm() > 1e-6 )
              road.centreline.push_back( p.head<2>() );
          }
          if ( road.centreline.size() >= 2 )
            roads.push_back( road );
        }
        OGR_F_Destroy( feature );
      }
      if ( roads.empty() )
        throw std::invalid_argument( "the road layer " + path + " has no line features" );
      return roads;
    }

    //! A projected CRS for a DEM: its own, or the UTM zone of its centre when it is geographic.
    std::string blockCrsForDem( const Dem &dem, std::vector<std::string> &notes )
    {
      if ( !dem.isGeographic() )
        return dem.crsWkt();
      const std::array<double, 6> &gt = dem.geoTransform();
      const double lon = gt[0] + 0.5 * dem.width() * gt[1], lat = gt[3] + 0.5 * dem.height() * gt[5];
      const int zone = std::clamp( static_cast<int>( std::floor( ( lon + 180.0 ) / 6.0 ) ) + 1, 1, 60 );
      const std::string crs = "EPSG:" + std::to_string( ( lat >= 0 ? 32600 : 32700 ) + zone );
      notes.push_back( "the DEM is geographic; the block CRS is " + crs + " (UTM zone of its centre)" );
      return crs;
    }

    //! Bounding box of the DEM's covered area in the block CRS (edges sampled).
    void demExtentInBlock( const Dem &dem, const std::string &blockCrs, Eigen::Vector2d &lo, Eigen::Vector2d &hi )
    {
      CrsTransform toBlock( dem.crsWkt(), blockCrs );
      const std::array<double, 6> &gt = dem.geoTransform();
      lo = Eigen::Vector2d::Constant( std::numeric_limits<double>::infinity() );
      hi = -lo;
      constexpr int kSamples = 32;
      for ( int k = 0; k <= kSamples; ++k )
        for ( int edge = 0; edge < 4; ++edge )
        {
          const double f = static_cast<double>( k ) / kSamples;
          // cell-centre extent
          const double c = 0.5 + ( edge < 2 ? f * ( dem.width() - 1 ) : ( edge == 2 ? 0 : dem.width() - 1 ) );
          const double r = 0.5 + ( edge < 2 ? ( edge == 0 ? 0 : dem.height() - 1 ) : f * ( dem.height() - 1 ) );
          const Eigen::Vector3d p = toBlock.transform( Eigen::Vector3d( gt[0] + c * gt[1] + r * gt[2], gt[3] + c * gt[4] + r * gt[5], 0.0 ) );
          if ( std::isfinite( p.x() ) && std::isfinite( p.y() ) )
          {
            lo = lo.cwiseMin( p.head<2>() );
            hi = hi.cwiseMax( p.head<2>() );
          }
        }
      if ( dem.isGeographic() || !toBlock.isIdentity() )
      {
        // a reprojected rectangle is not a rectangle: keep inside it
        const Eigen::Vector2d inset = ( hi - lo ) * 0.03;
        lo += inset;
        hi -= inset;
      }
    }

    std::shared_ptr<OrthoTexture> loadOrtho( const std::string &path, const std::string &blockCrs, const Eigen::Vector2d &lo, const Eigen::Vector2d &hi )
    {
      GDALAllRegister();
      GDALDatasetH source = GDALOpen( path.c_str(), GA_ReadOnly );
      if ( !source )
        throw std::invalid_argument( "the orthophoto " + path + " cannot be opened" );
      const bool hasCrs = GDALGetSpatialRef( source ) != nullptr;
      if ( !hasCrs )
      {
        GDALClose( source );
        throw std::invalid_argument( "the orthophoto " + path + " has no CRS" );
      }
      std::vector<std::string> args { "-of", "MEM", "-t_srs", blockCrs, "-te", fmt( lo.x() ), fmt( lo.y() ), fmt( hi.x() ), fmt( hi.y() ),
                                      "-r", "bilinear", "-dstalpha" };
      std::vector<char *> argv;
      for ( std::string &a : args )
        argv.push_back( a.data() );
      argv.push_back( nullptr );
      GDALWarpAppOptions *options = GDALWarpAppOptionsNew( argv.data(), nullptr );
      int usageError = 0;
      GDALDatasetH warped = GDALWarp( "", nullptr, 1, &source, options, &usageError );
      GDALWarpAppOptionsFree( options );
      GDALClose( source );
      if ( !warped )
        throw std::invalid_argument( "the orthophoto " + path + " cannot be reprojected to the block CRS" );
      const int width = GDALGetRasterXSize( warped ), height = GDALGetRasterYSize( warped ), bands = GDALGetRasterCount( warped );
      auto ortho = std::make_shared<OrthoTexture>();
      double gt[6];
      GDALGetGeoTransform( warped, gt );
      ortho->originX = gt[0];
      ortho->originY = gt[3];
      ortho->pixelSizeM = gt[1];
      ortho->rgb = cv::Mat( height, width, CV_8UC3 );
      std::vector<uint8_t> band( static_cast<size_t>( width ) * height ), alpha( band.size(), 255 );
      bool readOk = GDALRasterIO( GDALGetRasterBand( warped, bands ), GF_Read, 0, 0, width, height, alpha.data(), width, height, GDT_Byte, 0, 0 ) == CE_None;
      long covered = 0;
      for ( uint8_t a : alpha )
        covered += a > 0 ? 1 : 0;
      for ( int k = 0; k < 3; ++k )
      {
        const int b = std::min( k + 1, std::max( 1, bands - 1 ) );
        readOk = readOk && GDALRasterIO( GDALGetRasterBand( warped, b ), GF_Read, 0, 0, width, height, band.data(), width, height, GDT_Byte, 0, 0 ) == CE_None;
        for ( int r = 0; r < height; ++r )
          for ( int c = 0; c < width; ++c )
            ortho->rgb.at<cv::Vec3b>( r, c )[k] = band[static_cast<size_t>( r ) * width + c];
      }
      GDALClose( warped );
      if ( !readOk )
        throw std::invalid_argument( "the orthophoto " + path + " cannot be read" );
      if ( covered < 0.05 * width * height )
        throw std::invalid_argument( "the orthophoto " + path + " does not overlap the scene" );
      return ortho;
    }
  }

  std::string surveyPresetName( SurveyPreset preset )
  {
    switch ( preset )
    {
      case SurveyPreset::Highway:
        return "highway";
      case SurveyPreset::AerialStereo:
        return "aerial_stereo";
      case SurveyPreset::ObliquePhoto:
        return "oblique_photo";
    }
    return "highway";
  }

  SurveyPreset surveyPresetFromName( const std::string &name )
  {
    for ( SurveyPreset preset : { SurveyPreset::Highway, SurveyPreset::AerialStereo, SurveyPreset::ObliquePhoto } )
      if ( surveyPresetName( preset ) == name )
        return preset;
    throw std::invalid_argument( "unknown preset \"" + name + "\": use highway, aerial_stereo or oblique_photo" );
  }

  BuiltScene buildScene( const SceneRequest &request )
  {
    BuiltScene built;
    std::unique_ptr<Dem> dem;
    if ( !request.demPath.empty() )
    {
      try
      {
        dem = std::make_unique<Dem>( request.demPath );
      }
      catch ( const std::exception &e )
      {
        throw std::invalid_argument( e.what() );
      }
      built.crs = blockCrsForDem( *dem, built.notes );
    }
    else
    {
      built.crs = kProceduralCrs;
    }

    // Roads and the site centre.
    std::vector<Road> roads;
    Eigen::Vector2d demLo, demHi;
    if ( dem )
      demExtentInBlock( *dem, built.crs, demLo, demHi );
    if ( !request.roadsPath.empty() )
    {
      roads = loadRoads( request.roadsPath, built.crs, built.notes );
      Eigen::Vector2d lo = roads.front().centreline.front(), hi = lo;
      for ( const Eigen::Vector2d &p : roads.front().centreline )
      {
        lo = lo.cwiseMin( p );
        hi = hi.cwiseMax( p );
      }
      built.siteCentre = request.preset == SurveyPreset::Highway ? roads.front().centreline.front() : 0.5 * ( lo + hi );
      if ( dem && ( hi.x() < demLo.x() || lo.x() > demHi.x() || hi.y() < demLo.y() || lo.y() > demHi.y() ) )
        throw std::invalid_argument( "the road layer does not overlap the DEM (roads " + fmt( lo.x() ) + ", " + fmt( lo.y() ) + " to " + fmt( hi.x() ) + ", " +
                                     fmt( hi.y() ) + ", DEM " + fmt( demLo.x() ) + ", " + fmt( demLo.y() ) + " to " + fmt( demHi.x() ) + ", " + fmt( demHi.y() ) +
                                     " in the block CRS)" );
    }
    else
    {
      built.siteCentre = dem ? Eigen::Vector2d( 0.5 * ( demLo + demHi ) ) : Eigen::Vector2d( kSiteX, kSiteY );
      roads = proceduralRoads( request.preset, built.siteCentre );
    }

    // The terrain extent: the request around the site centre, inside the DEM.
    Eigen::Vector2d lo = built.siteCentre + request.extentMin, hi = built.siteCentre + request.extentMax;
    if ( dem )
    {
      lo = lo.cwiseMax( demLo );
      hi = hi.cwiseMin( demHi );
      if ( !( lo.x() < hi.x() && lo.y() < hi.y() ) )
        throw std::invalid_argument( "the DEM does not overlap the scene" );
    }
    double spacing = request.nodeSpacingM;
    while ( ( hi.x() - lo.x() ) / spacing * ( hi.y() - lo.y() ) / spacing > 30e6 )
      spacing *= 1.5;
    if ( spacing != request.nodeSpacingM )
      built.notes.push_back( "terrain nodes every " + fmt( spacing ) + " m to keep the grid under 30 million nodes" );
    const int width = static_cast<int>( std::floor( ( hi.x() - lo.x() ) / spacing ) ) + 1;
    const int height = static_cast<int>( std::floor( ( hi.y() - lo.y() ) / spacing ) ) + 1;
    if ( width < 8 || height < 8 )
      throw std::invalid_argument( "the DEM covers too little of the scene (under 8 x 8 terrain nodes)" );

    // Ground before the roads are cut in.
    const uint32_t seed = request.seed;
    const double hillAmplitude = request.preset == SurveyPreset::ObliquePhoto ? 22.0 : ( request.preset == SurveyPreset::AerialStereo ? 8.0 : 6.0 );
    const Eigen::Vector2d c0 = built.siteCentre;
    std::unique_ptr<CrsTransform> toDem = dem ? std::make_unique<CrsTransform>( built.crs, dem->crsWkt() ) : nullptr;
    const auto roadLevel = [&]( double x, double y ) // smooth surface the roads follow (procedural)
    {
      const double lx = x - c0.x(), ly = y - c0.y();
      return 200.0 + 0.012 * lx + 0.006 * ly + 2.0 * std::sin( lx / 170.0 ) * std::cos( ly / 230.0 );
    };
    double demFallback = 0.0;
    const auto ground = [&]( double x, double y ) -> double
    {
      if ( dem )
      {
        const Eigen::Vector3d p = toDem->transform( Eigen::Vector3d( x, y, 0.0 ) );
        const std::optional<double> h = dem->heightAt( p.x(), p.y() );
        return h ? *h : std::numeric_limits<double>::quiet_NaN();
      }
      const double lx = x - c0.x(), ly = y - c0.y();
      const double hills = std::sin( lx / 55.0 + 1.3 ) * std::cos( ly / 70.0 ) + 0.7 * noise::fbm( lx, ly, 120.0, 3, 1.0, seed + 101 );
      return roadLevel( x, y ) + hillAmplitude * hills;
    };
    if ( dem )
    {
      double sum = 0.0;
      int count = 0;
      for ( int k = 0; k < 64; ++k )
        if ( const double h = ground( lo.x() + ( hi.x() - lo.x() ) * ( k % 8 + 0.5 ) / 8, lo.y() + ( hi.y() - lo.y() ) * ( k / 8 + 0.5 ) / 8 ); std::isfinite( h ) )
        {
          sum += h;
          ++count;
        }
      if ( count == 0 )
        throw std::invalid_argument( "the DEM has no heights where the scene is" );
      demFallback = sum / count;
    }

    RoadNetwork network( roads );
    // Road height profiles: the ground along the centre line, smoothed over +-15 m; side roads meet the road they join.
    std::vector<std::vector<double>> profiles( roads.size() );
    for ( size_t r = 0; r < roads.size(); ++r )
    {
      const int n = static_cast<int>( std::ceil( network.length( static_cast<int>( r ) ) ) ) + 1;
      std::vector<double> raw( n );
      for ( int k = 0; k < n; ++k )
      {
        const Eigen::Vector2d p = network.pointAt( static_cast<int>( r ), k, 0.0 );
        double h = dem ? ground( p.x(), p.y() ) : roadLevel( p.x(), p.y() );
        raw[k] = std::isfinite( h ) ? h : std::numeric_limits<double>::quiet_NaN();
      }
      std::vector<double> &profile = profiles[r];
      profile.resize( n );
      for ( int k = 0; k < n; ++k )
      {
        double sum = 0.0;
        int count = 0;
        for ( int m = std::max( 0, k - 15 ); m <= std::min( n - 1, k + 15 ); ++m )
          if ( std::isfinite( raw[m] ) )
          {
            sum += raw[m];
            ++count;
          }
        profile[k] = count ? sum / count : demFallback;
      }
      for ( size_t q = 0; q < r; ++q )
        for ( int k = 0; k < n; ++k )
        {
          const Eigen::Vector2d p = network.pointAt( static_cast<int>( r ), k, 0.0 );
          const std::optional<RoadLocation> other = network.nearestCentreline( p.x(), p.y(), 1e9 );
          if ( !other || other->road != static_cast<int>( q ) )
            continue;
          const double reach = roads[q].halfWidthM() + 25.0;
          const double w = smoothstep( roads[q].halfWidthM(), reach, std::abs( other->d ) );
          const double sq = std::clamp( other->s, 0.0, static_cast<double>( profiles[q].size() - 1 ) );
          const double target = profiles[q][static_cast<size_t>( std::lround( sq ) )];
          profile[k] = ( 1 - w ) * target + w * profile[k];
        }
    }
    const auto roadZ = [&]( const RoadLocation &location )
    {
      const std::vector<double> &profile = profiles[location.road];
      const double s = std::clamp( location.s, 0.0, static_cast<double>( profile.size() - 1 ) );
      const size_t k = std::min( static_cast<size_t>( s ), profile.size() - 2 );
      const double f = s - k;
      return ( 1 - f ) * profile[k] + f * profile[k + 1];
    };
    long filled = 0;
    HeightField terrain( lo.x(), hi.y(), spacing, width, height, [&]( double x, double y )
    {
      double g = ground( x, y );
      if ( !std::isfinite( g ) )
      {
        ++filled;
        g = demFallback;
      }
      const std::optional<RoadLocation> location = network.nearestCentreline( x, y, 1e9 );
      if ( !location )
        return g;
      const Road &road = roads[location->road];
      const double edge = road.halfWidthM() + kKerbWidthM + kShoulderWidthM;
      const double w = smoothstep( edge, edge + kBlendReachM, std::abs( location->d ) );
      return ( 1 - w ) * roadZ( *location ) + w * g;
    } );
    if ( filled > 0 )
      built.notes.push_back( std::to_string( filled ) + " terrain nodes outside the DEM's data took its mean height" );
    if ( dem && dem->filledCellCount() > 0 )
      built.notes.push_back( std::to_string( dem->filledCellCount() ) + " DEM cells without data were filled from their neighbours" );

    // Objects, ground marks and control targets along the roads.
    std::mt19937 random( seed * 7919u + 17u );
    std::uniform_real_distribution<double> jitter( -1.0, 1.0 );
    std::vector<SceneObject> objects;
    std::vector<GroundMark> marks;
    int poles = 0, signs = 0, hydrants = 0, trees = 0, cars = 0, manholes = 0, targets = 0;
    const auto heightAt = [&]( const Eigen::Vector2d &p ) { return terrain.heightAt( p.x(), p.y() ); };
    const auto freeSpot = [&]( const Eigen::Vector2d &p, double radius, int road, bool offRoad )
    {
      if ( !terrain.covers( p.x(), p.y() ) )
        return false;
      const std::optional<RoadLocation> at = network.locate( p.x(), p.y() );
      if ( offRoad && at )
        return false;
      if ( !offRoad && ( !at || at->road != road ) )
        return false;
      for ( const SceneObject &o : objects )
        if ( ( o.base.head<2>() - p ).norm() < radius + o.footprintRadiusM() + 0.3 )
          return false;
      for ( const GroundMark &m : marks )
        if ( ( m.centre.head<2>() - p ).norm() < radius + m.reachM() + 0.3 )
          return false;
      return true;
    };
    const auto addObject = [&]( ObjectKind kind, const std::string &id, const Eigen::Vector2d &p, double heading, const Eigen::Vector3f &colour )
    {
      SceneObject o;
      o.id = id;
      o.kind = kind;
      o.base = Eigen::Vector3d( p.x(), p.y(), *heightAt( p ) );
      o.headingRad = heading;
      o.colour = colour;
      objects.push_back( o );
    };
    const auto id = []( const char *prefix, int n )
    {
      char buffer[32];
      std::snprintf( buffer, sizeof buffer, "%s%03d", prefix, n );
      return std::string( buffer );
    };
    const Eigen::Vector3f carColours[] = { { 0.7f, 0.1f, 0.1f }, { 0.15f, 0.25f, 0.6f }, { 0.85f, 0.85f, 0.85f }, { 0.1f, 0.1f, 0.1f }, { 0.5f, 0.5f, 0.45f } };
    const double targetRadius = request.targetRadiusM;
    const auto addTarget = [&]( const Eigen::Vector2d &p )
    {
      GroundMark m;
      m.id = id( "GCP", ++targets );
      m.kind = GroundMarkKind::Target;
      m.centre = Eigen::Vector3d( p.x(), p.y(), *heightAt( p ) );
      m.radiusM = targetRadius;
      m.squareHalfM = 1.6 * targetRadius;
      marks.push_back( m );
    };
    for ( size_t r = 0; r < roads.size(); ++r )
    {
      const Road &road = roads[r];
      const int ri = static_cast<int>( r );
      const double length = network.length( ri );
      const double hw = road.halfWidthM();
      const double outside = hw + kKerbWidthM;
      Eigen::Vector2d tangent;
      for ( double s = 12.0; s < length; s += 30.0 )
      {
        const double side = ( static_cast<int>( s / 30.0 ) % 2 ) ? 1.0 : -1.0;
        const Eigen::Vector2d p = network.pointAt( ri, s + 2.0 * jitter( random ), side * ( outside + kShoulderWidthM + 0.6 ), &tangent );
        if ( freeSpot( p, 0.2, ri, true ) )
          addObject( ObjectKind::Pole, id( "pole_", ++poles ), p, 0.0, Eigen::Vector3f( 0.62f, 0.63f, 0.66f ) );
      }
      for ( double s = 25.0; s < length; s += 70.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, -( outside + 0.8 ), &tangent );
        if ( freeSpot( p, 0.5, ri, false ) )
          addObject( ObjectKind::Sign, id( "sign_", ++signs ), p, std::atan2( -tangent.y(), -tangent.x() ), Eigen::Vector3f::Zero() );
      }
      for ( double s = 40.0; s < length; s += 55.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, outside + 1.0, &tangent );
        if ( freeSpot( p, 0.3, ri, false ) )
          addObject( ObjectKind::Hydrant, id( "hydrant_", ++hydrants ), p, 0.0, Eigen::Vector3f( 0.8f, 0.12f, 0.08f ) );
      }
      for ( double s = 8.0; s < length; s += 14.0 )
        for ( double side : { -1.0, 1.0 } )
        {
          const Eigen::Vector2d p = network.pointAt( ri, s + 4.0 * jitter( random ), side * ( outside + kShoulderWidthM + 4.0 + 3.0 * std::abs( jitter( random ) ) ) );
          if ( jitter( random ) > -0.2 && freeSpot( p, 2.3, ri, true ) )
            addObject( ObjectKind::Tree, id( "tree_", ++trees ), p, 0.0,
                       Eigen::Vector3f( 0.16f, 0.3f, 0.1f ) * static_cast<float>( 1.0 + 0.2 * jitter( random ) ) );
        }
      for ( double s = 60.0; s < length; s += 65.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, hw - 1.05, &tangent );
        if ( freeSpot( p, 2.4, ri, false ) && !network.onHigherPriorityRoad( ri, p.x(), p.y() ) )
        {
          const std::string carId = id( "car_", ++cars );
          addObject( ObjectKind::Car, carId, p, std::atan2( tangent.y(), tangent.x() ) + kPi, carColours[cars % 5] );
        }
      }
      for ( double s = 30.0; s < length; s += 45.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, -0.5 * road.laneWidthM + 0.9, &tangent );
        if ( freeSpot( p, 0.35, ri, false ) && !network.onHigherPriorityRoad( ri, p.x(), p.y() ) )
        {
          GroundMark m;
          m.id = id( "manhole_", ++manholes );
          m.kind = GroundMarkKind::Manhole;
          m.centre = Eigen::Vector3d( p.x(), p.y(), *heightAt( p ) );
          m.radiusM = 0.32;
          marks.push_back( m );
        }
      }
      const double targetSpacing = request.preset == SurveyPreset::Highway ? 20.0 : std::max( 25.0, 60.0 * targetRadius );
      for ( double s = 15.0; s < length; s += targetSpacing )
      {
        const double side = ( static_cast<int>( s / targetSpacing ) % 2 ) ? 1.0 : -1.0;
        const double half = 1.6 * targetRadius;
        const Eigen::Vector2d p = network.pointAt( ri, s, side * ( outside + std::max( 0.5 * kShoulderWidthM, half + 0.1 ) ) );
        if ( freeSpot( p, half * 1.5, ri, request.preset != SurveyPreset::Highway ) || ( request.preset == SurveyPreset::Highway && freeSpot( p, half * 1.5, ri, false ) ) )
          addTarget( p );
      }
    }
    // Open-field targets and trees for the aerial and oblique scenes.
    if ( request.preset != SurveyPreset::Highway )
    {
      std::uniform_real_distribution<double> ux( lo.x() + 5, hi.x() - 5 ), uy( lo.y() + 5, hi.y() - 5 );
      const double area = ( hi.x() - lo.x() ) * ( hi.y() - lo.y() );
      const int fieldTargets = std::clamp( static_cast<int>( area / ( 5000.0 * targetRadius * targetRadius ) ), 8, 60 );
      for ( int k = 0, tries = 0; k < fieldTargets && tries < 20 * fieldTargets; ++tries )
      {
        const Eigen::Vector2d p( ux( random ), uy( random ) );
        const double half = 1.6 * targetRadius;
        if ( !freeSpot( p, half * 1.5, -1, true ) )
          continue;
        addTarget( p );
        ++k;
      }
      const int fieldTrees = std::clamp( static_cast<int>( area / ( request.preset == SurveyPreset::ObliquePhoto ? 4000.0 : 1500.0 ) ), 10, 3000 );
      for ( int k = 0, tries = 0; k < fieldTrees && tries < 10 * fieldTrees; ++tries )
      {
        const Eigen::Vector2d p( ux( random ), uy( random ) );
        if ( !freeSpot( p, 2.3, -1, true ) )
          continue;
        addObject( ObjectKind::Tree, id( "tree_", ++trees ), p, 0.0, Eigen::Vector3f( 0.16f, 0.3f, 0.1f ) * static_cast<float>( 1.0 + 0.2 * jitter( random ) ) );
        ++k;
      }
    }

    built.scene = std::make_unique<Scene>( std::move( terrain ), std::move( network ), std::move( objects ), std::move( marks ), SceneLighting(), seed );
    built.scene->setTextureFloorM( request.textureFloorM );
    if ( !request.orthoPath.empty() )
    {
      built.scene->setOrtho( loadOrtho( request.orthoPath, built.crs, lo, hi ) );
      built.notes.push_back( "ground texture from the orthophoto " + request.orthoPath );
    }
    return built;
  }

} // namespace geostation
