/***************************************************************************
  imageprefetcher.cpp
 ***************************************************************************/
#include "workstation/imageprefetcher.h"

#include <algorithm>
#include <stdexcept>

#include "workstation/matchimagecache.h"

namespace geostation
{

  ImagePrefetcher::ImagePrefetcher( std::shared_ptr<MatchImageCache> cache )
    : ImagePrefetcher( cache ? LoadFunction( [cache]( const std::string &path ) { cache->get( path ); } ) : LoadFunction() )
  {
  }

  ImagePrefetcher::ImagePrefetcher( LoadFunction load )
    : mLoad( std::move( load ) )
  {
    if ( !mLoad )
      throw std::invalid_argument( "ImagePrefetcher: no cache or load function to prepare images with" );
    mWorker = std::thread( [this] { run(); } );
  }

  ImagePrefetcher::~ImagePrefetcher()
  {
    {
      std::lock_guard<std::mutex> lock( mMutex );
      mStopping = true;
      mSummary.superseded += mPending.size();
      mPending.clear();
    }
    mChanged.notify_all();
    mWorker.join();
  }

  void ImagePrefetcher::prefetch( const std::vector<std::string> &paths )
  {
    {
      std::lock_guard<std::mutex> lock( mMutex );
      mSummary.superseded += mPending.size();
      mPending.clear();
      for ( const std::string &path : paths )
      {
        if ( path.empty() || std::find( mPending.begin(), mPending.end(), path ) != mPending.end() )
          continue;
        mPending.push_back( path );
        ++mSummary.requested;
      }
    }
    mChanged.notify_all();
  }

  bool ImagePrefetcher::waitUntilIdle( std::chrono::milliseconds timeout ) const
  {
    std::unique_lock<std::mutex> lock( mMutex );
    return mChanged.wait_for( lock, timeout, [this] { return mPending.empty() && !mLoading; } );
  }

  ImagePrefetcher::Summary ImagePrefetcher::summary() const
  {
    std::lock_guard<std::mutex> lock( mMutex );
    return mSummary;
  }

  void ImagePrefetcher::run()
  {
    std::unique_lock<std::mutex> lock( mMutex );
    for ( ;; )
    {
      mChanged.wait( lock, [this] { return mStopping || !mPending.empty(); } );
      if ( mStopping )
        return;
      const std::string path = mPending.front();
      mPending.pop_front();
      mLoading = true;
      lock.unlock();
      bool failed = false;
      try
      {
        mLoad( path );
      }
      catch ( ... )
      {
        // a prefetch is a convenience: the operator's own request reads the image again and reports why not
        failed = true;
      }
      lock.lock();
      mLoading = false;
      ++( failed ? mSummary.failed : mSummary.loaded );
      mChanged.notify_all();
    }
  }

} // namespace geostation
