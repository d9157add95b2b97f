/***************************************************************************
  pixelspacegpkg.cpp - GeoPackage layers in image (pixel) space
 ***************************************************************************/
#include "io/pixelspacegpkg.h"
#include "io/rasterfile.h"

#include <stdexcept>
#include <vector>

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_api.h>

namespace geostation
{

  namespace
  {
    //! SQL string literal / identifier quoting.
    std::string sqlQuoted( const std::string &text, char quote )
    {
      std::string out( 1, quote );
      for ( char c : text )
      {
        out += c;
        if ( c == quote )
          out += c;
      }
      return out + quote;
    }

    void execute( GDALDatasetH ds, const std::string &sql )
    {
      CPLErrorReset();
      OGRLayerH result = GDALDatasetExecuteSQL( ds, sql.c_str(), nullptr, nullptr );
      if ( result )
        GDALDatasetReleaseResultSet( ds, result );
      if ( CPLGetLastErrorType() >= CE_Failure )
        throw std::runtime_error( std::string( "GeoPackage update failed: " ) + CPLGetLastErrorMsg() );
    }
  } // namespace

  namespace
  {
    GDALDatasetH openForUpdate( const std::filesystem::path &file )
    {
      const char *drivers[] = { "GPKG", nullptr };
      CPLPushErrorHandler( CPLQuietErrorHandler );
      GDALDatasetH ds = GDALOpenEx( file.string().c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, drivers, nullptr, nullptr );
      CPLPopErrorHandler();
      if ( !ds )
        throw std::runtime_error( "cannot open " + file.string() + " as a GeoPackage for update" );
      return ds;
    }
  } // namespace

  namespace
  {
    //! The named layer (an empty name: the file's only one); closes the dataset and throws where there is none.
    OGRLayerH layerOf( GDALDatasetH ds, const std::filesystem::path &file, const std::string &layerName )
    {
      OGRLayerH layer = layerName.empty() ? ( GDALDatasetGetLayerCount( ds ) == 1 ? GDALDatasetGetLayer( ds, 0 ) : nullptr )
                        : GDALDatasetGetLayerByName( ds, layerName.c_str() );
      if ( !layer )
      {
        GDALClose( ds );
        throw std::runtime_error( "no layer " + ( layerName.empty() ? std::string( "(the file has several; name one)" ) : "\"" + layerName + "\"" ) + " in " +
                                  file.string() );
      }
      return layer;
    }

    /**
     * Writes the layer's features again in one transaction - every one, or
     * only those with an empty geometry - storing NULL for each empty
     * geometry; returns how many were empty. Throws std::runtime_error.
     */
    int rewriteFeatures( const std::filesystem::path &file, const std::string &layerName, bool everyFeature )
    {
      GDALDatasetH ds = openForUpdate( file );
      OGRLayerH layer = layerOf( ds, file, layerName );
      bool ok = GDALDatasetStartTransaction( ds, FALSE ) == OGRERR_NONE;
      int emptied = 0;
      if ( ok )
      {
        OGR_L_ResetReading( layer );
        std::vector<OGRFeatureH> features;
        while ( OGRFeatureH f = OGR_L_GetNextFeature( layer ) )
          features.push_back( f );
        for ( OGRFeatureH f : features )
        {
          const OGRGeometryH g = OGR_F_GetGeometryRef( f );
          const bool empty = g && OGR_G_IsEmpty( g );
          if ( empty )
          {
            OGR_F_SetGeometryDirectly( f, nullptr );
            ++emptied;
          }
          if ( empty || everyFeature )
            ok = ok && OGR_L_SetFeature( layer, f ) == OGRERR_NONE;
          OGR_F_Destroy( f );
        }
        ok = ok ? GDALDatasetCommitTransaction( ds ) == OGRERR_NONE : ( GDALDatasetRollbackTransaction( ds ), false );
      }
      const std::string name = OGR_L_GetName( layer );
      GDALClose( ds );
      if ( !ok )
        throw std::runtime_error( "rewriting the geometries of layer \"" + name + "\" in " + file.string() + " failed" );
      return emptied;
    }
  } // namespace

  void markGeoPackageLayerAsPixelSpace( const std::filesystem::path &file, const std::string &layerName )
  {
    registerGdalDrivers();
    GDALDatasetH ds = openForUpdate( file );
    const std::string name = OGR_L_GetName( layerOf( ds, file, layerName ) );
    try
    {
      const std::string table = sqlQuoted( name, '\'' );
      execute( ds, "UPDATE gpkg_contents SET srs_id = -1 WHERE table_name = " + table );
      execute( ds, "UPDATE gpkg_geometry_columns SET srs_id = -1 WHERE table_name = " + table );
    }
    catch ( ... )
    {
      GDALClose( ds );
      throw;
    }
    GDALClose( ds );
    // Each geometry blob repeats the srs_id in its header: every feature is written again, so the driver writes it
    // with the layer's new srs_id; an empty geometry (what QGIS writes for "no geometry") means nothing in pixel
    // space and becomes NULL
    rewriteFeatures( file, name, true );
  }

  int nullEmptyGeoPackageGeometries( const std::filesystem::path &file, const std::string &layerName )
  {
    registerGdalDrivers();
    return rewriteFeatures( file, layerName, false );
  }

} // namespace geostation
