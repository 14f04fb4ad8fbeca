/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * CSV files written by `rostopic echo -p TOPIC` (ROS 1): a header
 * "%time,field.header.seq,field.header.stamp,field.header.frame_id,..."
 * where %time (the receive time) and field.header.stamp are integer
 * nanoseconds since the epoch, and string fields (frame_id) sit between
 * the numbers.  The message fields of sensor_msgs/Imu, Temperature and
 * geometry_msgs/Vector3Stamped get the names and units of the bag reader
 * (gx..az in rad/s and m/s^2, header stamps as time); the rest (sequence
 * numbers, frame ids, orientation, covariances) stays readable by name but
 * out of the default selection.
 */
#include "internal.h"

#include <string.h>

#include "io-formats.h"

bool ssc_rostopic_detect(const char *first_name)
{
	return !strcmp(first_name, "%time");
}

void ssc_rostopic_column(const char *name, bool has_stamp,
			 const char **new_name, const char **unit,
			 bool *hidden)
{
	static const struct {
		const char *field, *name, *unit;
	} map[] = {
		{ "field.angular_velocity.x", "gx", "rad/s" },
		{ "field.angular_velocity.y", "gy", "rad/s" },
		{ "field.angular_velocity.z", "gz", "rad/s" },
		{ "field.linear_acceleration.x", "ax", "m/s^2" },
		{ "field.linear_acceleration.y", "ay", "m/s^2" },
		{ "field.linear_acceleration.z", "az", "m/s^2" },
		{ "field.vector.x", "x", NULL },
		{ "field.vector.y", "y", NULL },
		{ "field.vector.z", "z", NULL },
		{ "field.temperature", "temperature", "degC" },
	};

	*new_name = NULL;
	*unit = NULL;
	*hidden = true;
	if (!strcmp(name, "%time")) {
		*new_name = has_stamp ? "receive_time" : "time";
		*unit = "ns";
		return;
	}
	if (!strcmp(name, "field.header.stamp")) {
		*new_name = "time";
		*unit = "ns";
		return;
	}
	for (size_t i = 0; i < sizeof(map) / sizeof(map[0]); i++)
		if (!strcmp(name, map[i].field)) {
			*new_name = map[i].name;
			*unit = map[i].unit;
			*hidden = false;
			return;
		}
}
