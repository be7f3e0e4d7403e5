/* A PID controller for ambdrop over LCM, in C, built from the client kit alone (find_package
 * (ambdrop): the lcm-gen C types) and configured from the plant description (`ambdrop hil
 * --describe FILE`): per AMB its sensor's index and the static currents, and the reference
 * controller's gains in A/m. It answers every AMBDROP_SENSORS message with one AMBDROP_CURRENTS
 * message, so `ambdrop hil --controller lcm --virtual-clock --lockstep` runs it sample by sample.
 *
 *   lcm_pid [--url URL] --period-s T --kp A_PER_M --ki A_PER_M_S --kd A_S_PER_M --tf S
 *           --limit-A A --amb SENSOR,STATIC_X_A,STATIC_Y_A [--amb ...] [--idle-exit-s S]
 *           [--swap-ends] [--silent]
 *
 * --amb once per AMB, in the plant description's index order. --swap-ends feeds each AMB the
 * other end's sensor and --silent never answers: two broken controllers a test bench must
 * catch. Per axis, with e = -reading (m):
 *   i = i_static + kp e + ki sum(e T) + d,  d += (kd (e - e_prev) / T - d) T / (tf + T),
 * clamped to +-limit, the integral held while the unclamped current is beyond the limit. */
#include <lcm/lcm.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ambdrop_lcm_amb_currents_t.h"
#include "ambdrop_lcm_sensor_readings_t.h"

#define MAX_AMBS 4

typedef struct {
  double integral, derivative, previous;
  int primed;
} axis_state;

typedef struct {
  lcm_t* lcm;
  int ambs;
  int sensor_of[MAX_AMBS];
  double static_A[MAX_AMBS][2];
  double kp, ki, kd, tf, period_s, limit_A;
  int swap_ends, silent;
  int64_t sequence;
  axis_state axis[MAX_AMBS][2];
  double last_message_s;
} controller;

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double pid(const controller* c, axis_state* s, double reading_m, double static_A) {
  const double e = -reading_m;
  const double T = c->period_s;
  if (!s->primed) {
    s->previous = e;
    s->primed = 1;
  }
  s->derivative += (c->kd * (e - s->previous) / T - s->derivative) * T / (c->tf + T);
  s->previous = e;
  const double candidate = s->integral + c->ki * e * T;
  if (fabs(c->kp * e + candidate + s->derivative + static_A) <= c->limit_A) s->integral = candidate;
  const double i = c->kp * e + s->integral + s->derivative + static_A;
  return i > c->limit_A ? c->limit_A : (i < -c->limit_A ? -c->limit_A : i);
}

static void on_sensors(const lcm_recv_buf_t* rbuf, const char* channel,
                       const ambdrop_lcm_sensor_readings_t* msg, void* user) {
  (void)rbuf;
  (void)channel;
  controller* c = (controller*)user;
  c->last_message_s = now_s();
  if (c->silent) return;
  ambdrop_lcm_amb_currents_t out;
  memset(&out, 0, sizeof out);
  out.sequence = ++c->sequence;
  out.amb_count = (int8_t)c->ambs;
  for (int a = 0; a < c->ambs; ++a) {
    const int sensor = c->sensor_of[c->swap_ends ? c->ambs - 1 - a : a];
    if (sensor >= msg->sensor_count) continue;
    out.current_x_A[a] = pid(c, &c->axis[a][0], msg->x_m[sensor], c->static_A[a][0]);
    out.current_y_A[a] = pid(c, &c->axis[a][1], msg->y_m[sensor], c->static_A[a][1]);
  }
  ambdrop_lcm_amb_currents_t_publish(c->lcm, "AMBDROP_CURRENTS", &out);
}

static int number(const char* flag, const char* text, double* out) {
  char* end = NULL;
  *out = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(*out)) {
    fprintf(stderr, "lcm_pid: %s %s: not a finite number\n", flag, text);
    return 0;
  }
  return 1;
}

int main(int argc, char** argv) {
  controller c;
  memset(&c, 0, sizeof c);
  const char* url = NULL;
  double idle_exit_s = 2.0;
  for (int k = 1; k < argc; ++k) {
    const char* flag = argv[k];
    if (strcmp(flag, "--swap-ends") == 0) {
      c.swap_ends = 1;
      continue;
    }
    if (strcmp(flag, "--silent") == 0) {
      c.silent = 1;
      continue;
    }
    if (k + 1 >= argc) {
      fprintf(stderr, "lcm_pid: %s needs a value\n", flag);
      return 64;
    }
    const char* value = argv[++k];
    int ok = 1;
    if (strcmp(flag, "--url") == 0) {
      url = value;
    } else if (strcmp(flag, "--period-s") == 0) {
      ok = number(flag, value, &c.period_s);
    } else if (strcmp(flag, "--kp") == 0) {
      ok = number(flag, value, &c.kp);
    } else if (strcmp(flag, "--ki") == 0) {
      ok = number(flag, value, &c.ki);
    } else if (strcmp(flag, "--kd") == 0) {
      ok = number(flag, value, &c.kd);
    } else if (strcmp(flag, "--tf") == 0) {
      ok = number(flag, value, &c.tf);
    } else if (strcmp(flag, "--limit-A") == 0) {
      ok = number(flag, value, &c.limit_A);
    } else if (strcmp(flag, "--idle-exit-s") == 0) {
      ok = number(flag, value, &idle_exit_s);
    } else if (strcmp(flag, "--amb") == 0) {
      int sensor = -1;
      if (c.ambs >= MAX_AMBS ||
          sscanf(value, "%d,%lf,%lf", &sensor, &c.static_A[c.ambs][0], &c.static_A[c.ambs][1]) !=
              3 ||
          sensor < 0 || sensor >= 8) {
        fprintf(stderr, "lcm_pid: --amb %s: expected SENSOR,STATIC_X_A,STATIC_Y_A (at most %d)\n",
                value, MAX_AMBS);
        return 64;
      }
      c.sensor_of[c.ambs++] = sensor;
    } else {
      fprintf(stderr, "lcm_pid: unknown flag %s\n", flag);
      return 64;
    }
    if (!ok) return 64;
  }
  if (c.ambs == 0 || !(c.period_s > 0.0) || !(c.limit_A > 0.0) || c.tf < 0.0) {
    fprintf(stderr, "lcm_pid: needs --amb, --period-s > 0 and --limit-A > 0\n");
    return 64;
  }
  c.lcm = lcm_create(url);
  if (c.lcm == NULL) {
    fprintf(stderr, "lcm_pid: cannot open LCM %s\n", url ? url : "(default)");
    return 1;
  }
  ambdrop_lcm_sensor_readings_t_subscribe(c.lcm, "AMBDROP_SENSORS", on_sensors, &c);
  c.last_message_s = now_s();
  while (now_s() - c.last_message_s < idle_exit_s) lcm_handle_timeout(c.lcm, 50);
  printf("lcm_pid: %lld currents messages sent\n", (long long)c.sequence);
  lcm_destroy(c.lcm);
  return 0;
}
