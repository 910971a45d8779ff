/* libconde_loopback_bind.so: makes roscpp's XML-RPC server listen where roscpp's own TCPROS
 * server listens.
 *
 * roscpp binds its TCPROS server to the loopback interface when ROS_IP is a loopback address
 * (127.x.x.x or ::1) or ROS_HOSTNAME is "localhost", but its XML-RPC server (xmlrpcpp) always
 * binds to every interface (0.0.0.0). On a lab network anyone could then call a node's XML-RPC
 * API (shutdown, publisherUpdate, ...). rospy and rosmaster already follow ROS_IP for both.
 *
 * Preloaded into every process of a sourced workspace (env hook of conde_bringup), this library
 * does nothing unless the process has libroscpp loaded and ROS_IP/ROS_HOSTNAME ask for loopback,
 * as roscpp's Transport decides; then a bind() to the wildcard address (0.0.0.0 or ::) binds to
 * the loopback address of the same family instead. Every other bind() is passed on unchanged.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

typedef int (*BindFunction)(int, const struct sockaddr*, socklen_t);

/* The rule of roscpp's Transport constructor (ros/transport/transport.cpp). */
static int loopback_requested(void) {
  const char* hostname = getenv("ROS_HOSTNAME");
  const char* ip = getenv("ROS_IP");
  if (hostname && strcmp(hostname, "localhost") == 0) return 1;
  if (ip && (strncmp(ip, "127.", 4) == 0 || strcmp(ip, "::1") == 0)) return 1;
  return 0;
}

static int find_roscpp(struct dl_phdr_info* info, size_t size, void* found) {
  (void)size;
  if (info->dlpi_name && strstr(info->dlpi_name, "/libroscpp.so")) *(int*)found = 1;
  return *(int*)found;
}

static int roscpp_loaded(void) {
  int found = 0;
  dl_iterate_phdr(find_roscpp, &found);
  return found;
}

int bind(int fd, const struct sockaddr* address, socklen_t length) {
  static BindFunction next_bind = NULL;
  if (!next_bind) next_bind = (BindFunction)dlsym(RTLD_NEXT, "bind");
  if (address && loopback_requested() && roscpp_loaded()) {
    if (address->sa_family == AF_INET && length >= (socklen_t)sizeof(struct sockaddr_in)) {
      struct sockaddr_in local;
      memcpy(&local, address, sizeof local);
      if (local.sin_addr.s_addr == htonl(INADDR_ANY)) {
        local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        return next_bind(fd, (const struct sockaddr*)&local, sizeof local);
      }
    } else if (address->sa_family == AF_INET6 && length >= (socklen_t)sizeof(struct sockaddr_in6)) {
      struct sockaddr_in6 local;
      memcpy(&local, address, sizeof local);
      if (memcmp(&local.sin6_addr, &in6addr_any, sizeof in6addr_any) == 0) {
        local.sin6_addr = in6addr_loopback;
        return next_bind(fd, (const struct sockaddr*)&local, sizeof local);
      }
    }
  }
  return next_bind(fd, address, length);
}
