/***************************************************************************
  scenesources.cpp - DEM, roads and orthophoto of a simulated scene
 ***************************************************************************/
#include "simulation/scenesources.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <cpl_conv.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "io/rasterfile.h"

namespace geostation
{
  namespace
  {
    struct OgrDataSourceCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };
  } // namespace

  std::string sceneNumber( double v )
  {
    std::ostringstream s;
    s.precision( 10 );
    s << v;
    return s.str();
  }

  //! Line features of an OGR layer as roads in the block CRS.
  std::vector<Road> loadRoads( const std::string &path, const std::string &blockCrs, std::vector<std::string> &notes )
  {
    registerGdalDrivers();
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
            throw std::invalid_argument( "vertex " + sceneNumber( x ) + ", " + sceneNumber( y ) + " of road " + road.id + " cannot be transformed to the block CRS" );
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
    registerGdalDrivers();
    GDALDatasetH source = GDALOpen( path.c_str(), GA_ReadOnly );
    if ( !source )
      throw std::invalid_argument( "the orthophoto " + path + " cannot be opened" );
    const bool hasCrs = GDALGetSpatialRef( source ) != nullptr;
    if ( !hasCrs )
    {
      GDALClose( source );
      throw std::invalid_argument( "the orthophoto " + path + " has no CRS" );
    }
    std::vector<std::string> args { "-of", "MEM", "-t_srs", blockCrs, "-te", sceneNumber( lo.x() ), sceneNumber( lo.y() ), sceneNumber( hi.x() ), sceneNumber( hi.y() ),
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

} // namespace geostation
