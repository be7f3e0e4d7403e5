/* A PID controller for ambdrop over SocketCAN, in C, on the frame map of a config's [can] table
 * through the header the kit generates from it (`ambdrop can-export CONFIG --header`; the
 * examples' CMakeLists.txt does that at build time). Configured as lcm_pid.c is, from the plant
 * description; its period is the frame map's exchange period. It answers each complete set of
 * sensor frames with the current frames.
 *
 *   can_pid --interface IFACE --kp A_PER_M --ki A_PER_M_S --kd A_S_PER_M --tf S --limit-A A
 *           --amb SENSOR,STATIC_X_A,STATIC_Y_A [--amb ...] [--idle-exit-s S] [--swap-ends]
 */
#include <errno.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <math.h>
#include <net/if.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "ambdrop_can_frames.h"

#define MAX_AMBS 4
#define MAX_SENSORS 8
#define MAX_IDS 8

typedef struct {
  double integral, derivative, previous;
  int primed;
} axis_state;

static double kp, ki, kd, tf, limit_A;

static double pid(axis_state* s, double T, double reading_m, double static_A) {
  const double e = -reading_m;
  if (!s->primed) {
    s->previous = e;
    s->primed = 1;
  }
  s->derivative += (kd * (e - s->previous) / T - s->derivative) * T / (tf + T);
  s->previous = e;
  const double candidate = s->integral + ki * e * T;
  if (fabs(kp * e + candidate + s->derivative + static_A) <= limit_A) s->integral = candidate;
  const double i = kp * e + s->integral + s->derivative + static_A;
  return i > limit_A ? limit_A : (i < -limit_A ? -limit_A : i);
}

static int number(const char* flag, const char* text, double* out) {
  char* end = NULL;
  *out = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(*out)) {
    fprintf(stderr, "can_pid: %s %s: not a finite number\n", flag, text);
    return 0;
  }
  return 1;
}

int main(int argc, char** argv) {
  const char* interface = NULL;
  double idle_exit_s = 2.0;
  int ambs = 0, swap_ends = 0;
  int sensor_of[MAX_AMBS];
  double static_A[MAX_AMBS][2];
  for (int k = 1; k < argc; ++k) {
    const char* flag = argv[k];
    if (strcmp(flag, "--swap-ends") == 0) {
      swap_ends = 1;
      continue;
    }
    if (k + 1 >= argc) {
      fprintf(stderr, "can_pid: %s needs a value\n", flag);
      return 64;
    }
    const char* value = argv[++k];
    int ok = 1;
    if (strcmp(flag, "--interface") == 0) {
      interface = value;
    } else if (strcmp(flag, "--kp") == 0) {
      ok = number(flag, value, &kp);
    } else if (strcmp(flag, "--ki") == 0) {
      ok = number(flag, value, &ki);
    } else if (strcmp(flag, "--kd") == 0) {
      ok = number(flag, value, &kd);
    } else if (strcmp(flag, "--tf") == 0) {
      ok = number(flag, value, &tf);
    } else if (strcmp(flag, "--limit-A") == 0) {
      ok = number(flag, value, &limit_A);
    } else if (strcmp(flag, "--idle-exit-s") == 0) {
      ok = number(flag, value, &idle_exit_s);
    } else if (strcmp(flag, "--amb") == 0) {
      int sensor = -1;
      if (ambs >= MAX_AMBS ||
          sscanf(value, "%d,%lf,%lf", &sensor, &static_A[ambs][0], &static_A[ambs][1]) != 3 ||
          sensor < 0 || sensor >= MAX_SENSORS) {
        fprintf(stderr, "can_pid: --amb %s: expected SENSOR,STATIC_X_A,STATIC_Y_A\n", value);
        return 64;
      }
      sensor_of[ambs++] = sensor;
    } else {
      fprintf(stderr, "can_pid: unknown flag %s\n", flag);
      return 64;
    }
    if (!ok) return 64;
  }
  if (interface == NULL || ambs == 0 || !(limit_A > 0.0) || tf < 0.0) {
    fprintf(stderr, "can_pid: needs --interface, --amb and --limit-A > 0\n");
    return 64;
  }
  int n_currents = 0, n_sensors = 0;
  const ambdrop_can_signal* currents = ambdrop_can_currents_in(&n_currents);
  const ambdrop_can_signal* sensors = ambdrop_can_sensors_out(&n_sensors);
  /* The frame ids of each direction: an exchange is complete once every sensor frame came. */
  uint32_t sensor_ids[MAX_IDS], current_ids[MAX_IDS];
  int n_sensor_ids = 0, n_current_ids = 0;
  for (int i = 0; i < n_sensors; ++i) {
    int seen = 0;
    for (int j = 0; j < n_sensor_ids; ++j) seen |= sensor_ids[j] == sensors[i].id;
    if (!seen && n_sensor_ids < MAX_IDS) sensor_ids[n_sensor_ids++] = sensors[i].id;
  }
  for (int i = 0; i < n_currents; ++i) {
    int seen = 0;
    for (int j = 0; j < n_current_ids; ++j) seen |= current_ids[j] == currents[i].id;
    if (!seen && n_current_ids < MAX_IDS) current_ids[n_current_ids++] = currents[i].id;
  }
  const double T = 1.0 / AMBDROP_CAN_EXCHANGE_RATE_HZ;

  const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  struct ifreq ifr;
  memset(&ifr, 0, sizeof ifr);
  strncpy(ifr.ifr_name, interface, IFNAMSIZ - 1);
  struct sockaddr_can addr;
  memset(&addr, 0, sizeof addr);
  addr.can_family = AF_CAN;
  if (fd < 0 || ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
    fprintf(stderr, "can_pid: %s: %s\n", interface, strerror(errno));
    return 1;
  }
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd, (struct sockaddr*)&addr, sizeof addr) < 0) {
    fprintf(stderr, "can_pid: bind %s: %s\n", interface, strerror(errno));
    return 1;
  }
  double readings[MAX_SENSORS][2] = {{0}};
  axis_state axis[MAX_AMBS][2];
  memset(axis, 0, sizeof axis);
  unsigned seen = 0;
  long answers = 0;
  struct pollfd p = {fd, POLLIN, 0};
  while (poll(&p, 1, (int)(idle_exit_s * 1000)) > 0) {
    struct can_frame frame;
    if (read(fd, &frame, sizeof frame) != (ssize_t)sizeof frame) continue;
    const uint32_t id = frame.can_id & CAN_EFF_MASK;
    int which = -1;
    for (int j = 0; j < n_sensor_ids; ++j) {
      if (sensor_ids[j] == id) which = j;
    }
    if (which < 0) continue;
    for (int i = 0; i < n_sensors; ++i) {
      if (sensors[i].id == id && sensors[i].byte_offset + sensors[i].width_bytes <= frame.len) {
        readings[sensors[i].index][sensors[i].axis] = ambdrop_can_get(frame.data, &sensors[i]);
      }
    }
    seen |= 1u << which;
    if (seen != (1u << n_sensor_ids) - 1u) continue;
    seen = 0;
    double out[MAX_AMBS][2];
    for (int a = 0; a < ambs; ++a) {
      const int s = sensor_of[swap_ends ? ambs - 1 - a : a];
      for (int x = 0; x < 2; ++x) out[a][x] = pid(&axis[a][x], T, readings[s][x], static_A[a][x]);
    }
    for (int j = 0; j < n_current_ids; ++j) {
      struct can_frame reply;
      memset(&reply, 0, sizeof reply);
      reply.can_id = current_ids[j];
      for (int i = 0; i < n_currents; ++i) {
        if (currents[i].id != current_ids[j] || currents[i].index >= ambs) continue;
        if (currents[i].extended) reply.can_id |= CAN_EFF_FLAG;
        ambdrop_can_set(reply.data, &currents[i], out[currents[i].index][currents[i].axis]);
        const int end = currents[i].byte_offset + currents[i].width_bytes;
        if (end > reply.len) reply.len = (uint8_t)end;
      }
      if (write(fd, &reply, sizeof reply) != (ssize_t)sizeof reply) {
        fprintf(stderr, "can_pid: write: %s\n", strerror(errno));
      }
    }
    ++answers;
  }
  printf("can_pid: %ld exchanges answered\n", answers);
  close(fd);
  return 0;
}
