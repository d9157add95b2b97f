// Image-space GeoPackage layers say "Cartesian, no CRS" (srs_id -1).
#include <filesystem>

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "io/pixelspacegpkg.h"

using namespace geostation;

namespace
{
  int queryInt( GDALDatasetH ds, const std::string &sql )
  {
    OGRLayerH result = GDALDatasetExecuteSQL( ds, sql.c_str(), nullptr, nullptr );
    EXPECT_NE( result, nullptr ) << sql;
    OGRFeatureH f = OGR_L_GetNextFeature( result );
    const int value = OGR_F_GetFieldAsInteger( f, 0 );
    OGR_F_Destroy( f );
    GDALDatasetReleaseResultSet( ds, result );
    return value;
  }
} // namespace

TEST( PixelSpaceGeoPackage, LayerBecomesUndefinedCartesian )
{
  GDALAllRegister();
  const std::filesystem::path file = std::filesystem::temp_directory_path() / ( "geostation-pixels-" + std::to_string( ::getpid() ) + ".gpkg" );
  std::filesystem::remove( file );
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GPKG" ), file.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr );
  ASSERT_NE( ds, nullptr );
  OGRLayerH layer = GDALDatasetCreateLayer( ds, "pixels", nullptr, wkbPoint, nullptr );
  for ( int i = 0; i < 3; ++i )
  {
    OGRFeatureH f = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
    OGRGeometryH g = OGR_G_CreateGeometry( wkbPoint );
    OGR_G_SetPoint_2D( g, 0, 210.5 + i, -130.25 );
    OGR_F_SetGeometryDirectly( f, g );
    ASSERT_EQ( OGR_L_CreateFeature( layer, f ), OGRERR_NONE );
    OGR_F_Destroy( f );
  }
  OGRFeatureH empty = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
  OGR_F_SetGeometryDirectly( empty, OGR_G_CreateGeometry( wkbPoint ) );
  ASSERT_EQ( OGR_L_CreateFeature( layer, empty ), OGRERR_NONE );
  OGR_F_Destroy( empty );
  GDALClose( ds );

  markGeoPackageLayerAsPixelSpace( file );

  ds = GDALOpenEx( file.string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
  ASSERT_NE( ds, nullptr );
  EXPECT_EQ( queryInt( ds, "SELECT srs_id FROM gpkg_contents WHERE table_name = 'pixels'" ), -1 );
  EXPECT_EQ( queryInt( ds, "SELECT srs_id FROM gpkg_geometry_columns WHERE table_name = 'pixels'" ), -1 );
  EXPECT_EQ( queryInt( ds, "SELECT count(*) FROM pixels WHERE hex(substr(geom, 5, 4)) = 'FFFFFFFF'" ), 3 );
  EXPECT_EQ( queryInt( ds, "SELECT count(*) FROM pixels WHERE geom IS NULL" ), 1 );
  layer = GDALDatasetGetLayer( ds, 0 );
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef( layer );
  ASSERT_NE( srs, nullptr );
  EXPECT_STREQ( OSRGetName( srs ), "Undefined Cartesian SRS" );
  OGRFeatureH f = OGR_L_GetNextFeature( layer );
  EXPECT_DOUBLE_EQ( OGR_G_GetX( OGR_F_GetGeometryRef( f ), 0 ), 210.5 );
  EXPECT_DOUBLE_EQ( OGR_G_GetY( OGR_F_GetGeometryRef( f ), 0 ), -130.25 );
  OGR_F_Destroy( f );
  GDALClose( ds );
  std::filesystem::remove( file );
}

TEST( PixelSpaceGeoPackage, MissingFileOrLayerThrows )
{
  EXPECT_THROW( markGeoPackageLayerAsPixelSpace( "/nonexistent/x.gpkg" ), std::runtime_error );
}
