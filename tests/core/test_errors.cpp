#include <gtest/gtest.h>
#include <mrpt/core/exceptions.h>
#include <superloc/core/errors.h>

#include <stdexcept>

using superloc::oneLineError;

TEST(OneLineError, PlainExceptionKeepsItsText) {
    EXPECT_EQ(oneLineError(std::runtime_error("map.pcd: truncated after 12 points")),
              "map.pcd: truncated after 12 points");
}

TEST(OneLineError, MrptExceptionLosesBannerAndCallTrace) {
    try {
        THROW_EXCEPTION("rawlog.gz: entry 3: corrupt");
    } catch (const std::exception& e) {
        const std::string msg = oneLineError(e);
        EXPECT_NE(msg.find("rawlog.gz: entry 3: corrupt"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos);
        EXPECT_EQ(msg.find("===="), std::string::npos);
    }
}
