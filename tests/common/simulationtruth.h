// The simulator's truth.gpkg read back for tests: control points, objects,
// the number of road lines, the image truth (point, image) -> pixel and, for
// control targets, how much of the white disc each image shows.
// Throws std::runtime_error when the file or a layer is missing.
#ifndef GEOSTATION_TESTS_SIMULATIONTRUTH_H
#define GEOSTATION_TESTS_SIMULATIONTRUTH_H

#include <filesystem>
#include <map>
#include <string>

#include <Eigen/Core>
#include <gdal.h>
#include <stdexcept>
#include <ogr_api.h>
#include <ogr_srs_api.h>

namespace geostation
{
  struct TruthTable
  {
    std::map<std::string, Eigen::Vector3d> control, objects;
    std::map<std::pair<std::string, std::string>, Eigen::Vector2d> imageTruth; // (point, image) -> pixel
    struct Disc
    {
      double px = 0.0, inView = 0.0, inSun = 0.0; // white disc's area in the image, fractions in view and in sunlight
    };
    std::map<std::pair<std::string, std::string>, Disc> targetDiscs; // (control point, image) -> its disc there
    int roads = 0;
    std::string controlCrsName;
  };

  inline TruthTable readTruth( const std::filesystem::path &gpkg )
  {
    TruthTable truth;
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx( gpkg.string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
    if ( !ds )
      throw std::runtime_error( "cannot open the simulation truth " + gpkg.string() );
    const auto require = [&]( OGRLayerH layer, const char *name )
    {
      if ( !layer )
      {
        GDALClose( ds );
        throw std::runtime_error( std::string( "the simulation truth has no layer " ) + name );
      }
      return layer;
    };
    for ( const char *name : { "control", "objects" } )
    {
      OGRLayerH layer = require( GDALDatasetGetLayerByName( ds, name ), name );
      if ( std::string( name ) == "control" && OGR_L_GetSpatialRef( layer ) )
        truth.controlCrsName = OSRGetName( OGR_L_GetSpatialRef( layer ) );
      while ( OGRFeatureH f = OGR_L_GetNextFeature( layer ) )
      {
        OGRGeometryH g = OGR_F_GetGeometryRef( f );
        ( std::string( name ) == "control" ? truth.control : truth.objects )[OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "id" ) )] =
          Eigen::Vector3d( OGR_G_GetX( g, 0 ), OGR_G_GetY( g, 0 ), OGR_G_GetZ( g, 0 ) );
        OGR_F_Destroy( f );
      }
    }
    OGRLayerH roads = require( GDALDatasetGetLayerByName( ds, "roads" ), "roads" );
    truth.roads = static_cast<int>( OGR_L_GetFeatureCount( roads, TRUE ) );
    OGRLayerH table = require( GDALDatasetGetLayerByName( ds, "image_truth" ), "image_truth" );
    while ( OGRFeatureH f = OGR_L_GetNextFeature( table ) )
    {
      truth.imageTruth[{ OGR_F_GetFieldAsString( f, 0 ), OGR_F_GetFieldAsString( f, 1 ) }] = Eigen::Vector2d( OGR_F_GetFieldAsDouble( f, 2 ), OGR_F_GetFieldAsDouble( f, 3 ) );
      if ( OGR_F_GetFieldCount( f ) >= 7 && OGR_F_IsFieldSetAndNotNull( f, 4 ) )
        truth.targetDiscs[{ OGR_F_GetFieldAsString( f, 0 ), OGR_F_GetFieldAsString( f, 1 ) }] = { OGR_F_GetFieldAsDouble( f, 4 ), OGR_F_GetFieldAsDouble( f, 5 ), OGR_F_GetFieldAsDouble( f, 6 ) };
      OGR_F_Destroy( f );
    }
    GDALClose( ds );
    return truth;
  }

}

#endif // GEOSTATION_TESTS_SIMULATIONTRUTH_H
