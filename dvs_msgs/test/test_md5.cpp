// The MD5 sums of our messages must equal those of the ecosystem's dvs_msgs
// (rpg_dvs_ros, ESIM, Event Camera Dataset), or existing bags will not play into our nodes.
#include <dvs_msgs/Event.h>
#include <dvs_msgs/EventArray.h>
#include <gtest/gtest.h>
#include <ros/message_traits.h>

#include <string>

TEST(DvsMsgs, EventMd5MatchesEcosystem)
{
  EXPECT_EQ(std::string("40d339b261445b8ce9a6fef01267cd5d"),
            ros::message_traits::MD5Sum<dvs_msgs::Event>::value());
  EXPECT_EQ(std::string("dvs_msgs/Event"), ros::message_traits::DataType<dvs_msgs::Event>::value());
}

TEST(DvsMsgs, EventArrayMd5MatchesEcosystem)
{
  EXPECT_EQ(std::string("5e8beee5a6c107e504c2e78903c224b8"),
            ros::message_traits::MD5Sum<dvs_msgs::EventArray>::value());
  EXPECT_EQ(std::string("dvs_msgs/EventArray"),
            ros::message_traits::DataType<dvs_msgs::EventArray>::value());
}

TEST(DvsMsgs, SerializedEventIsThirteenBytes)
{
  // uint16 x, uint16 y, time ts (2 x uint32), bool polarity = 13 bytes on the wire.
  dvs_msgs::Event e;
  EXPECT_EQ(13u, ros::serialization::serializationLength(e));
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
