// The Multiview's background preparation of images: loads in the order asked,
// requests the operator has passed dropped, a failed load not the end of the
// worker, no load outliving the prefetcher, and (run under ThreadSanitizer by
// scripts/sanitize.sh --thread) the cache shared with the operator's clicks.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "workstation/imageprefetcher.h"
#include "workstation/matchimagecache.h"

using namespace geostation;
using namespace std::chrono_literals;

namespace
{
  //! A load function that records what it loads and holds the load of one path until released.
  class HeldLoads
  {
    public:
      explicit HeldLoads( std::string held ) : mHeld( std::move( held ) ) {}

      ImagePrefetcher::LoadFunction function()
      {
        return [this]( const std::string &path )
        {
          std::unique_lock<std::mutex> lock( mMutex );
          mStarted.push_back( path );
          mChanged.notify_all();
          if ( path == mHeld )
            mChanged.wait( lock, [this] { return mReleased; } );
          if ( path == "throws" )
            throw std::bad_alloc();
          mFinished.push_back( path );
        };
      }
      bool waitForStart( const std::string &path )
      {
        std::unique_lock<std::mutex> lock( mMutex );
        return mChanged.wait_for( lock, 10s, [&] { return std::find( mStarted.begin(), mStarted.end(), path ) != mStarted.end(); } );
      }
      void release()
      {
        std::lock_guard<std::mutex> lock( mMutex );
        mReleased = true;
        mChanged.notify_all();
      }
      std::vector<std::string> finished() const
      {
        std::lock_guard<std::mutex> lock( mMutex );
        return mFinished;
      }

    private:
      std::string mHeld;
      mutable std::mutex mMutex;
      std::condition_variable mChanged;
      bool mReleased = false;
      std::vector<std::string> mStarted, mFinished;
  };
}

TEST( ImagePrefetcher, LoadsInOrderAndDropsTheRequestsPassed )
{
  HeldLoads loads( "station1/left" );
  ImagePrefetcher prefetcher( loads.function() );
  prefetcher.prefetch( { "station1/left" } );
  ASSERT_TRUE( loads.waitForStart( "station1/left" ) );
  // the operator steps on twice while the first image loads: station 2's images are passed before they start
  prefetcher.prefetch( { "station2/left", "station2/right" } );
  prefetcher.prefetch( { "station3/left", "", "station3/right", "station3/left" } );
  EXPECT_FALSE( prefetcher.waitUntilIdle( 50ms ) );
  loads.release();
  ASSERT_TRUE( prefetcher.waitUntilIdle( 10s ) );
  EXPECT_EQ( loads.finished(), ( std::vector<std::string> { "station1/left", "station3/left", "station3/right" } ) );
  const ImagePrefetcher::Summary summary = prefetcher.summary();
  EXPECT_EQ( summary.requested, 5u ); // the empty path and the repeat are not requests
  EXPECT_EQ( summary.loaded, 3u );
  EXPECT_EQ( summary.superseded, 2u );
  EXPECT_EQ( summary.failed, 0u );
}

TEST( ImagePrefetcher, AFailedLoadIsCountedAndTheWorkerGoesOn )
{
  HeldLoads loads( "" );
  ImagePrefetcher prefetcher( loads.function() );
  prefetcher.prefetch( { "throws", "next" } );
  ASSERT_TRUE( prefetcher.waitUntilIdle( 10s ) );
  EXPECT_EQ( loads.finished(), std::vector<std::string> { "next" } );
  EXPECT_EQ( prefetcher.summary().failed, 1u );
  EXPECT_EQ( prefetcher.summary().loaded, 1u );
  EXPECT_THROW( ImagePrefetcher( ImagePrefetcher::LoadFunction() ), std::invalid_argument );
  EXPECT_THROW( ImagePrefetcher( std::shared_ptr<MatchImageCache>() ), std::invalid_argument );
}

TEST( ImagePrefetcher, DestroyedWithRequestsPendingWaitsForTheLoadInProgressOnly )
{
  HeldLoads loads( "a" );
  std::thread releaser;
  {
    ImagePrefetcher prefetcher( loads.function() );
    prefetcher.prefetch( { "a", "b", "c" } );
    ASSERT_TRUE( loads.waitForStart( "a" ) );
    releaser = std::thread( [&loads] {
      std::this_thread::sleep_for( 100ms );
      loads.release();
    } );
  } // the destructor returns only once "a" is done; "b" and "c" are dropped
  EXPECT_EQ( loads.finished(), std::vector<std::string> { "a" } );
  releaser.join();
}

TEST( ImagePrefetcher, PreparesStationsIntoTheCacheTheOperatorReads )
{
  // a run of eight stations of one image each: at each station the Multiview asks for this image and the next,
  // and the operator's click reads this one at once, often while the prefetcher is loading it
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-prefetch-" + std::to_string( ::getpid() ) );
  std::filesystem::create_directories( dir );
  std::vector<std::string> paths;
  std::vector<cv::Mat> truth;
  for ( int i = 0; i < 8; ++i )
  {
    cv::Mat pixels( 240, 320, CV_8UC1 );
    cv::randu( pixels, 0, 255 );
    paths.push_back( ( dir / ( "station" + std::to_string( i ) + ".png" ) ).string() );
    ASSERT_TRUE( cv::imwrite( paths.back(), pixels ) );
    truth.push_back( pixels );
  }
  const size_t imageBytes = size_t( 320 ) * 240 * 9;
  auto cache = std::make_shared<MatchImageCache>( 18, 4 * imageBytes );
  int wrong = 0;
  {
    ImagePrefetcher prefetcher( cache );
    for ( int round = 0; round < 3; ++round )
      for ( size_t s = 0; s < paths.size(); ++s )
      {
        prefetcher.prefetch( { paths[s], paths[( s + 1 ) % paths.size()] } );
        const MatchImageCache::Entry entry = cache->get( paths[s] );
        if ( !entry.image || entry.image->width() != 320 || entry.image->bytes() != imageBytes )
        {
          ++wrong;
          continue;
        }
        for ( const cv::Point p : { cv::Point( 0, 0 ), cv::Point( 319, 239 ), cv::Point( 160, 120 ) } )
          wrong += entry.image->valueAt( p.x, p.y ) != static_cast<float>( truth[s].at<uint8_t>( p ) );
        if ( cache->bytes() > 4 * imageBytes )
          ++wrong;
      }
    ASSERT_TRUE( prefetcher.waitUntilIdle( 30s ) );
    const ImagePrefetcher::Summary summary = prefetcher.summary();
    EXPECT_EQ( summary.requested, 48u );
    EXPECT_EQ( summary.loaded + summary.superseded, summary.requested );
    EXPECT_EQ( summary.failed, 0u );
    // the last request was the last station's image and the first's: both are ready
    EXPECT_TRUE( cache->contains( paths.back() ) );
    EXPECT_TRUE( cache->contains( paths.front() ) );
    // stepping on and closing the Multiview at once: the prefetcher goes with its loads pending
    prefetcher.prefetch( paths );
  }
  EXPECT_EQ( wrong, 0 );
  EXPECT_LE( cache->bytes(), 4 * imageBytes );
  const MatchImageCache::Entry after = cache->get( paths[3] );
  ASSERT_TRUE( after.image );
  EXPECT_EQ( after.image->valueAt( 5, 7 ), static_cast<float>( truth[3].at<uint8_t>( 7, 5 ) ) );
  std::filesystem::remove_all( dir );
}
