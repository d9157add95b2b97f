/***************************************************************************
  photoimport.cpp - a single photo added to a block (Add Photo)
 ***************************************************************************/
#include "io/photoimport.h"
#include "io/rasterfile.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <gdal.h>
#include <cpl_error.h>
#include <cpl_string.h>

namespace geostation
{
  namespace
  {
    GDALDatasetH openRaster( const std::filesystem::path &photo )
    {
      registerGdalDrivers();
      if ( !std::filesystem::exists( photo ) )
        throw std::runtime_error( "The photo " + photo.string() + " does not exist." );
      CPLPushErrorHandler( CPLQuietErrorHandler );
      GDALDatasetH dataset = GDALOpenEx( photo.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
      CPLPopErrorHandler();
      if ( !dataset || GDALGetRasterCount( dataset ) < 1 )
      {
        if ( dataset )
          GDALClose( dataset );
        throw std::runtime_error( "The photo " + photo.string() + " cannot be decoded as an image." );
      }
      return dataset;
    }
  } // namespace

  std::string PhotoFileCamera::orientationNote() const
  {
    static const char *const shown[] = { "", "as stored", "mirrored left to right", "turned 180 degrees", "mirrored top to bottom", "mirrored across its diagonal",
                                         "turned 90 degrees clockwise", "mirrored across its other diagonal", "turned 90 degrees anticlockwise" };
    if ( exifOrientation <= 1 || exifOrientation > 8 )
      return std::string();
    const std::string tagged = "the file is tagged to be shown " + std::string( shown[exifOrientation] ) + " (EXIF orientation " + std::to_string( exifOrientation ) + ")";
    return tagged + "; its views show it so, but its pixels are measured as stored and its camera is that of the stored pixels";
  }

  ExifView viewForExifOrientation( int tag )
  {
    switch ( tag )
    {
      case 2:
        return { true, 0 };
      case 3:
        return { false, 180 };
      case 4:
        return { true, 180 };
      case 5:
        return { true, 270 };
      case 6:
        return { false, 90 };
      case 7:
        return { true, 90 };
      case 8:
        return { false, 270 };
      default:
        return {};
    }
  }

  PhotoFileCamera cameraFromPhotoFile( const std::filesystem::path &photo, const std::string &cameraId )
  {
    GDALDatasetH dataset = openRaster( photo );
    PhotoFileCamera result;
    Camera &camera = result.camera;
    camera.id = cameraId;
    camera.width = GDALGetRasterXSize( dataset );
    camera.height = GDALGetRasterYSize( dataset );
    camera.cx = 0.5 * camera.width;
    camera.cy = 0.5 * camera.height;
    const double diagonalPx = std::hypot( camera.width, camera.height );
    const std::optional<double> focal35 = exifNumber( dataset, "EXIF_FocalLengthIn35mmFilm" );
    const std::optional<double> focalMm = exifNumber( dataset, "EXIF_FocalLength" );
    const std::optional<double> planeResolution = exifNumber( dataset, "EXIF_FocalPlaneXResolution" );
    const std::optional<double> planeUnit = exifNumber( dataset, "EXIF_FocalPlaneResolutionUnit" );
    result.exifOrientation = exifOrientationTag( dataset );
    GDALClose( dataset );
    // 35 mm film's diagonal: 43.27 mm
    if ( focalMm && planeResolution && planeUnit && ( *planeUnit == 2.0 || *planeUnit == 3.0 ) )
    {
      const double pixelsPerMm = *planeResolution / ( *planeUnit == 2.0 ? 25.4 : 10.0 );
      camera.f = *focalMm * pixelsPerMm;
      result.focalSource = "exif_focal_plane_resolution";
    }
    else if ( focal35 )
    {
      camera.f = *focal35 / 43.27 * diagonalPx;
      result.focalSource = "exif_35mm_equivalent";
    }
    else
    {
      camera.f = 50.0 / 43.27 * diagonalPx;
      result.focalSource = "normal_lens_default";
    }
    camera.validate();
    return result;
  }

  Camera cameraFromJsonText( const std::string &json )
  {
    // read exactly as the block file reads a camera: inside a minimal block
    const std::string text = R"({"format": "geostation-block", "version": 1, "crs": "EPSG:25832", "cameras": [)" + json + R"(], "images": []})";
    const Block block = Block::fromJsonText( text, "camera" );
    return block.cameras.at( 0 );
  }

  Block newPhotoBlock( const std::string &crs, const std::filesystem::path &file )
  {
    Block block;
    block.crs = crs;
    block.sourceFile = file;
    return block;
  }

  std::string addPhotoToBlock( Block &block, const std::filesystem::path &photo, const Camera &camera )
  {
    GDALDatasetH dataset = openRaster( photo );
    const int width = GDALGetRasterXSize( dataset ), height = GDALGetRasterYSize( dataset );
    GDALClose( dataset );
    const Camera *existing = block.findCamera( camera.id );
    const Camera &used = existing ? *existing : camera;
    if ( !existing )
      camera.validate();
    if ( width != used.width || height != used.height )
      throw std::runtime_error( "The photo " + photo.filename().string() + " is " + std::to_string( width ) + " x " + std::to_string( height ) + " pixels but camera \"" +
                                used.id + "\" is " + std::to_string( used.width ) + " x " + std::to_string( used.height ) + "." );
    std::string id = photo.stem().string();
    if ( id.empty() )
      id = "photo";
    for ( int n = 2; block.findImage( id ); ++n )
      id = photo.stem().string() + "_" + std::to_string( n );
    if ( !existing )
      block.cameras.push_back( camera );
    BlockImage image;
    image.id = id;
    image.cameraId = used.id;
    const std::filesystem::path absolute = std::filesystem::absolute( photo ).lexically_normal();
    image.path = absolute.generic_string();
    if ( !block.sourceFile.empty() )
    {
      const std::filesystem::path relative = absolute.lexically_relative( std::filesystem::absolute( block.sourceFile ).parent_path().lexically_normal() );
      if ( !relative.empty() )
        image.path = relative.generic_string();
    }
    block.images.push_back( image );
    return id;
  }

} // namespace geostation
