/***************************************************************************
  matchimagecache.cpp
 ***************************************************************************/
#include "workstation/matchimagecache.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "io/rasterfile.h"

namespace geostation
{

  MatchImageCache::MatchImageCache( size_t capacity, size_t maxBytes, long long maxWholePixels )
    : mCapacity( std::max<size_t>( 1, capacity ) )
    , mMaxBytes( maxBytes )
    , mMaxWholePixels( maxWholePixels )
  {
    if ( maxWholePixels < 1 )
      throw std::invalid_argument( "MatchImageCache: the largest image prepared whole must have at least one pixel" );
  }

  size_t MatchImageCache::bytes() const
  {
    std::lock_guard<std::mutex> lock( mMutex );
    return mBytes;
  }

  namespace
  {
    //! "absent", or the file's size and last write time: what makes a remembered error stale.
    std::string fileStamp( const std::string &path )
    {
      std::error_code ec;
      const auto size = std::filesystem::file_size( path, ec );
      if ( ec )
        return "absent";
      const auto time = std::filesystem::last_write_time( path, ec );
      return std::to_string( size ) + "@" + std::to_string( ec ? 0 : time.time_since_epoch().count() );
    }
  }

  MatchImageCache::Entry MatchImageCache::get( const std::string &path )
  {
    return fetch( path, std::nullopt );
  }

  MatchImageCache::Entry MatchImageCache::get( const std::string &path, const cv::Rect &window )
  {
    if ( static_cast<long long>( window.width ) * window.height > mMaxWholePixels )
      throw std::invalid_argument( "a window of " + std::to_string( window.width ) + " x " + std::to_string( window.height ) + " pixels is larger than the " +
                                   std::to_string( mMaxWholePixels ) + " pixels prepared at once" );
    return fetch( path, window );
  }

  MatchImageCache::Entry MatchImageCache::read( const std::string &path, const std::optional<cv::Rect> &window ) const
  {
    Entry entry;
    try
    {
      // opened once: its size decides between the whole image and a window of it
      const RasterReader raster( path );
      entry.imageSize = raster.size();
      const cv::Rect whole( 0, 0, entry.imageSize.width, entry.imageSize.height );
      if ( static_cast<long long>( whole.width ) * whole.height <= mMaxWholePixels )
        entry.image = std::make_shared<const MatchImage>( raster.read( whole ).pixels );
      else if ( const cv::Rect asked = window ? *window & whole : cv::Rect(); !asked.empty() )
      {
        // the margin MatchImage holds but does not offer, around the pixels asked for
        const cv::Rect held = matchingWindowToRead( asked, entry.imageSize );
        entry.image = std::make_shared<const MatchImage>( raster.read( held ).pixels, held.tl(), entry.imageSize );
        entry.needsWindow = true;
      }
      else
        entry.needsWindow = true;
    }
    catch ( const std::exception &e )
    {
      entry = Entry();
      entry.status = Entry::Status::Unreadable;
      entry.message = e.what();
    }
    return entry;
  }

  MatchImageCache::Entry MatchImageCache::fetch( const std::string &path, const std::optional<cv::Rect> &window )
  {
    {
      std::unique_lock<std::mutex> lock( mMutex );
      mLoaded.wait( lock, [&] { return mLoading.count( path ) == 0; } );
      auto it = mEntries.find( path );
      if ( it != mEntries.end() && !it->second.ok() && mErrorStamps[path] != fileStamp( path ) )
      {
        // the file was put back or rewritten since it failed: read it again
        mEntries.erase( it ); // (an error holds no bytes)
        mOrder.remove( path );
        it = mEntries.end();
      }
      // an image read in windows: the window kept serves if it holds the pixels asked for (or none are asked for)
      if ( it != mEntries.end() && it->second.needsWindow && window )
      {
        const cv::Rect asked = *window & cv::Rect( 0, 0, it->second.imageSize.width, it->second.imageSize.height );
        if ( !it->second.image || !it->second.image->holds( asked ) )
        {
          mBytes -= it->second.image ? it->second.image->bytes() : 0;
          mEntries.erase( it );
          mOrder.remove( path );
          it = mEntries.end();
        }
      }
      if ( it != mEntries.end() )
      {
        mOrder.remove( path );
        mOrder.push_front( path );
        return it->second;
      }
      mLoading.insert( path );
    }
    const std::string stamp = fileStamp( path );
    const Entry entry = read( path, window );
    {
      std::lock_guard<std::mutex> lock( mMutex );
      mLoading.erase( path );
      mEntries[path] = entry;
      mBytes += entry.image ? entry.image->bytes() : 0;
      if ( entry.ok() )
        mErrorStamps.erase( path );
      else
        mErrorStamps[path] = stamp;
      mOrder.push_front( path );
      while ( mOrder.size() > mCapacity || ( mOrder.size() > 1 && mBytes > mMaxBytes ) )
      {
        const Entry &oldest = mEntries.at( mOrder.back() );
        mBytes -= oldest.image ? oldest.image->bytes() : 0;
        mEntries.erase( mOrder.back() );
        mErrorStamps.erase( mOrder.back() );
        mOrder.pop_back();
      }
    }
    mLoaded.notify_all();
    return entry;
  }

  bool MatchImageCache::contains( const std::string &path ) const
  {
    std::lock_guard<std::mutex> lock( mMutex );
    return mEntries.count( path ) > 0;
  }

  void MatchImageCache::clear()
  {
    std::lock_guard<std::mutex> lock( mMutex );
    mEntries.clear();
    mOrder.clear();
    mErrorStamps.clear();
    mBytes = 0;
  }

} // namespace geostation
