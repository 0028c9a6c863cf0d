# Find module for the ROS 1 bag library and the message headers of the ROS layer (ros/): Debian 12's
# librosbag-storage-dev, libsensor-msgs-dev, libgeometry-msgs-dev, libstd-msgs-dev, and the chunk
# decompressors libroslz4-dev and libbz2-dev (scripts/packages-ros.txt). Debian ships ROS 1 without catkin, and its rosbag_storage CMake config
# and pkg-config file cannot be used (they need ament's Python package and a pluginlib.pc), so the
# headers and libraries are found by name here. rosbag/bag.h includes the ROS 2 pluginlib that
# Debian builds it against, whose headers sit one folder down (/usr/include/pluginlib/pluginlib/).
# Sets Ros1Bag_FOUND, Ros1Bag_INCLUDE_DIRS and Ros1Bag_LIBRARIES.
set(_ros1bag_headers
  rosbag/bag.h sensor_msgs/Image.h sensor_msgs/CompressedImage.h sensor_msgs/CameraInfo.h
  sensor_msgs/FluidPressure.h sensor_msgs/Imu.h geometry_msgs/TwistWithCovarianceStamped.h
  std_msgs/Float64MultiArray.h roslz4/lz4s.h bzlib.h)
set(_ros1bag_vars)
foreach(header ${_ros1bag_headers})
  string(MAKE_C_IDENTIFIER "Ros1Bag_${header}" var)
  find_path(${var} ${header})
  list(APPEND _ros1bag_vars ${var})
endforeach()
# The ROS 2 headers that rosbag/bag.h reaches through pluginlib.
set(_ros1bag_nested pluginlib/class_loader.hpp class_loader/class_loader.hpp
                    rcpputils/shared_library.hpp rcutils/shared_library.h
                    ament_index_cpp/get_package_prefix.hpp)
set(_ros1bag_nested_dirs)
foreach(header ${_ros1bag_nested})
  string(MAKE_C_IDENTIFIER "Ros1Bag_${header}" var)
  get_filename_component(folder ${header} DIRECTORY)
  find_path(${var} ${header} PATH_SUFFIXES ${folder})
  list(APPEND _ros1bag_vars ${var})
  list(APPEND _ros1bag_nested_dirs ${${var}})
endforeach()
set(_ros1bag_libs)
foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge roslz4 bz2)
  find_library(Ros1Bag_${lib}_LIBRARY ${lib})
  list(APPEND _ros1bag_vars Ros1Bag_${lib}_LIBRARY)
  list(APPEND _ros1bag_libs ${Ros1Bag_${lib}_LIBRARY})
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Ros1Bag REQUIRED_VARS ${_ros1bag_vars})
if(Ros1Bag_FOUND)
  set(Ros1Bag_INCLUDE_DIRS ${Ros1Bag_rosbag_bag_h} ${_ros1bag_nested_dirs})
  list(REMOVE_DUPLICATES Ros1Bag_INCLUDE_DIRS)
  set(Ros1Bag_LIBRARIES ${_ros1bag_libs})
endif()
