/***************************************************************************
  colmapimport.cpp - a COLMAP sparse model as a GeoStation block
 ***************************************************************************/
#include "io/colmapimport.h"

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "geometry/crs.h"
#include "io/colmapconversion.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    //! Image ids: the name without its extension when that is unique, else the whole name.
    std::map<std::uint32_t, std::string> imageIds( const std::vector<const ColmapImage *> &images )
    {
      std::map<std::string, int> stemCount;
      for ( const ColmapImage *im : images )
        ++stemCount[fs::path( im->name ).replace_extension().generic_string()];
      std::map<std::uint32_t, std::string> ids;
      for ( const ColmapImage *im : images )
      {
        const std::string stem = fs::path( im->name ).replace_extension().generic_string();
        ids[im->id] = stemCount[stem] == 1 && !stem.empty() ? stem : im->name;
      }
      return ids;
    }

    /**
     * The exposure station of each imported image (block image id to station id) from the model's frames:
     * the images a rig took at one instant. The station is named after the image of the rig's reference
     * camera (else the frame's first image id), so stations sort as that camera's images do. Images in no
     * frame are left out (each becomes its own station). Throws std::invalid_argument for an image in two
     * frames or a frame that names an image's camera wrongly.
     */
    std::map<std::string, std::string> stationsFromFrames( const ColmapModel &model, const std::map<std::uint32_t, const ColmapImage *> &importedById,
                                                           const std::map<std::uint32_t, std::string> &idOf, BlockImportSummary &import )
    {
      std::map<std::string, std::string> stationOf;
      if ( model.frames.empty() )
        return stationOf;
      std::map<std::uint32_t, const ColmapRig *> rigById;
      for ( const ColmapRig &rig : model.rigs )
        rigById[rig.id] = &rig;
      std::set<std::uint32_t> modelImages;
      for ( const ColmapImage &im : model.images )
        modelImages.insert( im.id );
      std::map<std::uint32_t, std::uint32_t> frameOfImage;
      std::map<std::uint32_t, std::pair<int, size_t>> stationsPerRig; // rig: stations, most images in one
      int unknownImages = 0;
      for ( const ColmapFrame &frame : model.frames )
      {
        std::vector<std::pair<std::uint32_t, std::string>> members; // camera, block image id
        for ( const ColmapFrameData &d : frame.data )
        {
          if ( d.sensor.type != ColmapSensor::Type::Camera )
            continue;
          const std::uint32_t imageId = static_cast<std::uint32_t>( d.dataId );
          if ( d.dataId > std::numeric_limits<std::uint32_t>::max() || !modelImages.count( imageId ) )
          {
            ++unknownImages;
            continue;
          }
          const auto [previous, first] = frameOfImage.emplace( imageId, frame.id );
          if ( !first )
            throw std::invalid_argument( "the COLMAP model is inconsistent: image " + std::to_string( imageId ) + " is in frame " + std::to_string( previous->second )
                                         + " and in frame " + std::to_string( frame.id ) );
          const auto imported = importedById.find( imageId );
          if ( imported == importedById.end() )
            continue; // dropped, and said so
          if ( imported->second->cameraId != d.sensor.id )
            throw std::invalid_argument( "the COLMAP model is inconsistent: frame " + std::to_string( frame.id ) + " says image " + std::to_string( imageId ) + " (" + imported->second->name
                                         + ") was taken by camera " + std::to_string( d.sensor.id ) + ", the image says camera " + std::to_string( imported->second->cameraId ) );
          members.emplace_back( d.sensor.id, idOf.at( imageId ) );
        }
        if ( members.empty() )
          continue;
        std::string station = std::min_element( members.begin(), members.end(), []( const auto &a, const auto &b ) { return a.second < b.second; } )->second;
        const auto rig = rigById.find( frame.rigId );
        if ( rig != rigById.end() && rig->second->reference && rig->second->reference->type == ColmapSensor::Type::Camera )
          for ( const auto &[camera, imageId] : members )
            if ( camera == rig->second->reference->id )
              station = imageId;
        for ( const auto &member : members )
          stationOf[member.second] = station;
        auto &[stations, largest] = stationsPerRig[frame.rigId];
        ++stations;
        largest = std::max( largest, members.size() );
      }
      for ( const auto &[rigId, counts] : stationsPerRig )
      {
        const auto rig = rigById.find( rigId );
        std::string cameras;
        if ( rig != rigById.end() && rig->second->reference )
        {
          cameras = ", reference " + colmapSensorTypeName( rig->second->reference->type ) + " " + std::to_string( rig->second->reference->id );
          cameras += ", " + std::to_string( rig->second->others.size() + 1 ) + " sensor(s)";
        }
        import.converted.push_back( std::to_string( counts.first ) + " frame(s) of COLMAP rig " + std::to_string( rigId ) + cameras + " became exposure stations of up to "
                                    + std::to_string( counts.second ) + " image(s)" );
      }
      if ( unknownImages > 0 )
        import.dropped.push_back( std::to_string( unknownImages ) + " image(s) named by the COLMAP frames are not in the model's images (not registered)" );
      const size_t alone = std::count_if( importedById.begin(), importedById.end(), [&]( const auto &entry ) { return !frameOfImage.count( entry.first ); } );
      if ( alone > 0 )
        import.warnings.push_back( std::to_string( alone ) + " image(s) are in no COLMAP frame; each became a station of its own" );
      return stationOf;
    }
  }

  namespace
  {
    /**
     * Exposure stations from the image names, for a model whose frames hold
     * one image each or that has none: COLMAP's rig convention names a rig's
     * images by a folder per camera and the same file name at one instant
     * ("left/0001.jpg", "right/0001.jpg"), whatever camera model they share
     * (a single_camera model has one for all). Applies only when every
     * imported image lies in a folder, there are two folders or more, some
     * file name is in two of them and no folder holds a file name twice;
     * otherwise empty. A station is named after its image of the first
     * folder (in name order).
     */
    std::map<std::string, std::string> stationsFromFolders( const std::map<std::uint32_t, const ColmapImage *> &importedById,
                                                            const std::map<std::uint32_t, std::string> &idOf, BlockImportSummary &import )
    {
      std::map<std::string, std::vector<std::pair<std::string, std::string>>> byFileName; // file name: (folder, block image id)
      std::set<std::string> folders;
      for ( const auto &[colmapId, image] : importedById )
      {
        const fs::path name( image->name );
        if ( !name.has_parent_path() )
          return {};
        folders.insert( name.parent_path().generic_string() );
        byFileName[name.filename().generic_string()].emplace_back( name.parent_path().generic_string(), idOf.at( colmapId ) );
      }
      size_t largest = 0, shared = 0;
      for ( auto &[fileName, members] : byFileName )
      {
        std::sort( members.begin(), members.end() );
        for ( size_t k = 1; k < members.size(); ++k )
          if ( members[k].first == members[k - 1].first )
            return {};
        largest = std::max( largest, members.size() );
        shared += members.size() > 1 ? 1 : 0;
      }
      if ( folders.size() < 2 || largest < 2 )
        return {};
      std::map<std::string, std::string> stationOf;
      for ( const auto &[fileName, members] : byFileName )
        for ( const auto &member : members )
          stationOf[member.second] = members.front().second;
      std::string folderList;
      for ( const std::string &folder : folders )
        folderList += ( folderList.empty() ? "" : ", " ) + folder + "/";
      import.converted.push_back( std::to_string( shared ) + " file name(s) found in more than one of the folders " + folderList +
                                  " became exposure stations of up to " + std::to_string( largest ) + " image(s) (COLMAP's rig convention: a folder per camera)" );
      return stationOf;
    }
  }

  fs::path findColmapImageFolder( const ColmapModel &model, const fs::path &modelFolder )
  {
    if ( model.images.empty() )
      return {};
    const fs::path folder = fs::absolute( modelFolder ).lexically_normal();
    const fs::path parent = folder.parent_path();
    const fs::path grandparent = parent.parent_path();
    std::error_code ec;
    for ( const fs::path &candidate : { folder, parent / "images", grandparent / "images", parent, grandparent } )
      if ( fs::exists( candidate / model.images.front().name, ec ) )
        return candidate;
    return {};
  }

  namespace
  {
    //! The model's cameras into the block; returns the block camera id of each COLMAP camera kept (the others are reported dropped).
    std::map<std::uint32_t, std::string> addCameras( const ColmapModel &model, BlockImportSummary &import )
    {
      std::map<std::uint32_t, std::string> cameraIdOf;
      std::map<std::uint32_t, int> imagesPerCamera;
      for ( const ColmapImage &im : model.images )
        ++imagesPerCamera[im.cameraId];
      for ( const ColmapCamera &c : model.cameras )
      {
        const CameraFromColmap converted = cameraFromColmap( c, "camera" + std::to_string( c.id ) );
        if ( !converted.ok() )
        {
          import.dropped.push_back( converted.message + "; its " + std::to_string( imagesPerCamera[c.id] ) + " image(s) were dropped" );
          continue;
        }
        const Camera &camera = converted.camera;
        cameraIdOf[c.id] = camera.id;
        import.converted.push_back( "COLMAP camera " + std::to_string( c.id ) + " (" + c.model + ") became camera \"" + camera.id + "\" with lens model "
                                    + distortionModelName( camera.distortion.model ) );
        import.block.cameras.push_back( camera );
      }
      return cameraIdOf;
    }

    //! The 3-D points seen in two or more imported images (`importedById`, block ids `idOf`) as tie points with their observations.
    void addTiePoints( const ColmapModel &model, const std::map<std::uint32_t, const ColmapImage *> &importedById, const std::map<std::uint32_t, std::string> &idOf,
                       BlockImportSummary &import )
    {
      int pointsDropped = 0;
      std::set<std::uint64_t> seenPoints;
      for ( const ColmapPoint3D &p : model.points3D )
      {
        if ( !seenPoints.insert( p.id ).second )
          throw std::invalid_argument( "the COLMAP model has 3-D point id " + std::to_string( p.id ) + " twice" );
        std::vector<ImportedObservation> observations;
        std::set<std::uint32_t> imagesSeen;
        for ( const ColmapTrackElement &t : p.track )
        {
          auto it = importedById.find( t.imageId );
          if ( it == importedById.end() )
            continue;
          const ColmapImage &im = *it->second;
          if ( t.point2DIndex >= im.points2D.size() )
            throw std::invalid_argument( "the COLMAP model is inconsistent: 3-D point " + std::to_string( p.id ) + " is observed as 2-D point " + std::to_string( t.point2DIndex )
                                         + " of image " + std::to_string( im.id ) + ", which has " + std::to_string( im.points2D.size() ) );
          if ( !imagesSeen.insert( im.id ).second )
            continue; // one observation per image and point
          ImportedObservation o;
          o.pointId = std::to_string( p.id );
          o.imageId = idOf.at( im.id );
          o.pixelInImage = im.points2D[t.point2DIndex].pixel;
          observations.push_back( o );
        }
        if ( observations.size() < 2 || !p.xyz.allFinite() )
        {
          ++pointsDropped;
          continue;
        }
        ImportedTiePoint tie;
        tie.pointId = std::to_string( p.id );
        tie.world = p.xyz;
        tie.errorPx = p.error;
        import.tiePoints.push_back( tie );
        import.observations.insert( import.observations.end(), observations.begin(), observations.end() );
      }
      if ( !model.points3D.empty() )
        import.converted.push_back( std::to_string( import.tiePoints.size() ) + " 3-D point(s) became tie points with " + std::to_string( import.observations.size() ) + " image observations" );
      if ( pointsDropped > 0 )
        import.dropped.push_back( std::to_string( pointsDropped ) + " 3-D point(s) seen in fewer than two imported images were dropped" );
    }
  }

  BlockImportSummary importColmapModel( const ColmapModel &model, const fs::path &modelFolder, const ColmapImportOptions &options )
  {
    if ( options.crs.empty() )
      throw std::invalid_argument( "give the CRS the block is to be in (the model's own frame needs one too: a local engineering CRS in metres)" );
    requireProjectedMetricCrs( options.crs );

    BlockImportSummary import;
    bool binary = false;
    ColmapModel::modelFolder( modelFolder, &binary );
    import.format = binary ? "colmap-binary" : "colmap-text";
    Block &block = import.block;
    block.crs = options.crs;

    const std::map<std::uint32_t, std::string> cameraIdOf = addCameras( model, import );

    // images, in name order (capture order for most cameras' file names)
    std::vector<const ColmapImage *> images;
    std::set<std::uint32_t> seenIds;
    for ( const ColmapImage &im : model.images )
    {
      if ( !seenIds.insert( im.id ).second )
        throw std::invalid_argument( "the COLMAP model has image id " + std::to_string( im.id ) + " twice" );
      if ( !model.findCamera( im.cameraId ) )
        throw std::invalid_argument( "COLMAP image " + std::to_string( im.id ) + " (" + im.name + ") names camera " + std::to_string( im.cameraId ) + ", which the model does not have" );
      if ( cameraIdOf.count( im.cameraId ) )
        images.push_back( &im );
    }
    std::sort( images.begin(), images.end(), []( const ColmapImage *a, const ColmapImage *b ) { return a->name < b->name; } );
    const std::map<std::uint32_t, std::string> idOf = imageIds( images );
    std::map<std::uint32_t, const ColmapImage *> importedById;
    for ( const ColmapImage *im : images )
    {
      BlockImage image;
      image.id = idOf.at( im->id );
      image.cameraId = cameraIdOf.at( im->cameraId );
      image.path = im->name;
      try
      {
        image.exterior = exteriorFromColmapPose( im->qvec, im->tvec );
      }
      catch ( const std::invalid_argument &e )
      {
        import.dropped.push_back( "COLMAP image " + std::to_string( im->id ) + " (" + im->name + "): " + e.what() + "; dropped" );
        continue;
      }
      block.images.push_back( image );
      import.imageIdBySourceName[im->name] = image.id;
      importedById[im->id] = im;
    }
    if ( block.images.empty() )
      throw std::invalid_argument( "no image of the COLMAP model can be imported"
                                   + ( import.dropped.empty() ? std::string( ": the model has no registered images" ) : ": " + import.dropped.front() ) );
    // exposure stations: COLMAP's frames (3.12 and on), else the images of one name in a folder per camera, else one per image
    std::map<std::string, std::string> stationOf = stationsFromFrames( model, importedById, idOf, import );
    std::set<std::string> frameStations;
    for ( const auto &entry : stationOf )
      frameStations.insert( entry.second );
    const bool framesGroupImages = frameStations.size() < stationOf.size();
    if ( !framesGroupImages )
      if ( std::map<std::string, std::string> byFolder = stationsFromFolders( importedById, idOf, import ); !byFolder.empty() )
        stationOf = std::move( byFolder );
    std::set<std::string> stations;
    for ( BlockImage &image : block.images )
    {
      const auto found = stationOf.find( image.id );
      image.stationId = found != stationOf.end() ? found->second : image.id;
      if ( stations.insert( image.stationId ).second )
      {
        Station station;
        station.id = image.stationId;
        block.stations.push_back( station );
      }
    }
    import.converted.push_back( std::to_string( block.images.size() ) + " registered image(s) became oriented images"
                                + ( block.stations.size() == block.images.size() ? std::string( ", each its own station (no COLMAP frame or camera folder groups them)" )
                                                                                 : " in " + std::to_string( block.stations.size() ) + " exposure station(s)" ) );

    // image files
    fs::path imageFolder = options.imageFolder;
    if ( imageFolder.empty() )
      imageFolder = findColmapImageFolder( model, modelFolder );
    if ( imageFolder.empty() )
    {
      if ( options.requireImageFiles )
        throw std::invalid_argument( "the images of the COLMAP model were not found: \"" + model.images.front().name + "\" is neither beside the model in "
                                     + fs::absolute( modelFolder ).lexically_normal().string() + " nor in an \"images\" folder above it; give the image folder" );
      imageFolder = modelFolder;
    }
    block.sourceFile = fs::absolute( imageFolder ) / "colmap-import.geostation.json";
    if ( options.requireImageFiles )
    {
      for ( const BlockImage &image : block.images )
      {
        try
        {
          requireReadableImageFile( block, image );
        }
        catch ( const std::runtime_error &e )
        {
          throw std::invalid_argument( std::string( e.what() ) + " (image folder " + imageFolder.string() + ")" );
        }
      }
    }

    addTiePoints( model, importedById, idOf, import );
    return import;
  }

} // namespace geostation
