#!/bin/bash
# Runs a test program inside Debian's own kernel under qemu, where the hardware the host kernel
# lacks is real: SocketCAN (vcan0 up) and a simulated GPIO chip (gpio-sim, label "hil-sim",
# 8 lines, line 3 named "estop"). ctest's `hw` tests call it (tests/hw/CMakeLists.txt); so can
# a user's CI:
#
#   bash tests/hw/run_in_vm.sh build/tests/gpio_sim_test --gtest_color=no
#
# `run_in_vm.sh --prepare` sets up the cache (below) and exits: CI starts it beside the build,
# so that the downloads wait on the network while the compiler has the cores, not a test slot.
#
# The program and the shared libraries it links are copied into a busybox initramfs and run as
# root in the guest, with AMBDROP_REQUIRE_HW=1 so that tests which skip without the hardware
# fail there instead. The guest has no network device at all (-nic none). The guest's output is
# printed (kernel log lines dropped) and the script exits with the program's status.
#
# Exit status: the program's; 3 if the guest never reported one (crash, timeout: the raw console
# log is printed); 77 if the VM cannot be set up here (not root and packages missing, no Debian
# archive reachable, ...): ctest counts 77 as "skipped" (SKIP_RETURN_CODE).
#
# Environment:
#   VMWORK     cache folder (kernel, module build), default /tmp/ambdrop-vm
#   VMTIMEOUT  seconds before the guest is killed, default 300
#   VMEXTRA    more host programs to copy in (space-separated); candump, cansend, gpiodetect,
#              gpioinfo and gpiomon are always there
#   VMACCEL    qemu accelerator, default tcg (KVM is often unusable in CI VMs)
#   VMFILES    host files (configs, scenarios) copied into the guest's working folder /job
#   VMOUT      a host folder: what the guest's job leaves in /job/out is copied there when it
#              ends (tar + base64 over the console; the guest's files vanish at power-off)
#
# Cost: the first run downloads Debian's kernel and kernel sources and builds gpio-sim
# (~35-60 s); later runs boot from the cache (~6-20 s). Runs may go in parallel: the cache is
# set up under a lock, and each run has its own initramfs and console log.
#
# Needs (installed with apt-get when missing; root): qemu-system-x86 busybox-static xz-utils
# can-utils gpiod make gcc, and linux-headers-<abi> for the module build. Downloads
# linux-image-<abi> and linux-source-<ver> as .debs into the cache.
set -euo pipefail

[ $# -ge 1 ] || { echo "usage: $0 PROGRAM [ARGS...] | --prepare" >&2; exit 2; }
prepare_only=false
if [ "$1" = --prepare ]; then
  prepare_only=true
else
  [ -x "$1" ] || { echo "run_in_vm: $1 is not an executable (build it first)" >&2; exit 2; }
  PROG=$(readlink -f "$1"); shift
fi
W=${VMWORK:-/tmp/ambdrop-vm}
mkdir -p "$W"
export DEBIAN_FRONTEND=noninteractive

skip() { echo "run_in_vm: SKIPPED: cannot set up the VM here: $*" >&2; exit 77; }

# ---- Host packages, kernel and gpio-sim module: once per cache, under a lock -------------------
setup() {
  cd "$W"
  local need="qemu-system-x86 busybox-static xz-utils can-utils gpiod make gcc"
  if ! dpkg -s $need >/dev/null 2>&1; then
    [ "$(id -u)" = 0 ] || skip "missing packages ($need) and not root to install them"
    apt-get update -q >/dev/null || skip "apt-get update failed"
    apt-get install -y -q --no-install-recommends $need >/dev/null || skip "apt-get install $need failed"
  fi
  # Follow Debian's kernel metapackage, so a kernel update does not break the harness.
  if [ -z "$(apt-cache depends linux-image-amd64 2>/dev/null | grep 'Depends: linux-image-')" ]; then
    [ "$(id -u)" = 0 ] || skip "no apt package lists and not root to fetch them"
    apt-get update -q >/dev/null || skip "apt-get update failed"
  fi
  ABI=$(apt-cache depends linux-image-amd64 | awk '/Depends: linux-image-/{sub("linux-image-","",$2); print $2; exit}')
  [ -n "$ABI" ] || skip "apt knows no linux-image-amd64 (not a Debian system?)"
  KVER=$(apt-cache show "linux-image-$ABI" | awk '/^Version:/{print $2; exit}')
  if ! dpkg -s "linux-headers-$ABI" >/dev/null 2>&1; then
    [ "$(id -u)" = 0 ] || skip "linux-headers-$ABI missing and not root to install it"
    apt-get install -y -q --no-install-recommends "linux-headers-$ABI" >/dev/null \
      || skip "apt-get install linux-headers-$ABI failed"
  fi
  if [ ! -f "img-$ABI.deb" ]; then
    rm -f linux-image-*.deb
    apt-get download -q "linux-image-$ABI" >/dev/null 2>&1 || skip "apt-get download linux-image-$ABI failed"
    mv linux-image-"$ABI"_*.deb "img-$ABI.deb"
  fi
  if [ ! -d "kroot-$ABI" ]; then
    rm -rf "kroot-$ABI.tmp"
    dpkg-deb -x "img-$ABI.deb" "kroot-$ABI.tmp" && mv "kroot-$ABI.tmp" "kroot-$ABI"
  fi

  # Debian's kernels leave the GPIO simulator out: build gpio-sim and its irq_sim helper out of
  # tree from the matching linux-source package.
  if [ ! -f "mod-$ABI/gpio-sim.ko" ]; then
    local series; series=$(echo "$KVER" | cut -d. -f1-2)
    if [ ! -f "src-$KVER.deb" ]; then
      rm -f linux-source-*.deb
      apt-get download -q "linux-source-$series=$KVER" >/dev/null 2>&1 \
        || skip "apt-get download linux-source-$series=$KVER failed"
      mv linux-source-*.deb "src-$KVER.deb"
    fi
    rm -rf "mod-$ABI" "mod-$ABI.tmp"; mkdir -p "mod-$ABI.tmp"
    dpkg-deb --fsys-tarfile "src-$KVER.deb" | tar -xO --wildcards '*/linux-source-*.tar.xz' \
      | tar -xJf - -C "mod-$ABI.tmp" --strip-components=3 --wildcards \
          '*/drivers/gpio/gpio-sim.c' '*/drivers/gpio/gpiolib.h' '*/kernel/irq/irq_sim.c'
    ( cd "mod-$ABI.tmp"
      # irq_sim is built in only when some built-in driver selects it; as a module it may not
      # call the unexported handle_simple_irq() and needs a licence.
      sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' irq_sim.c
      grep -q MODULE_LICENSE irq_sim.c || printf '\n#include <linux/module.h>\nMODULE_LICENSE("GPL");\n' >> irq_sim.c
      echo 'obj-m += irq_sim.o gpio-sim.o' > Kbuild
      make -s -C "/lib/modules/$ABI/build" M="$PWD" modules >build.log 2>&1 \
        || { cat build.log >&2; echo "run_in_vm: building gpio-sim failed" >&2; exit 2; } )
    mv "mod-$ABI.tmp" "mod-$ABI"
  fi
  echo "$ABI" > abi
}

exec 9>"$W/.lock"
flock 9
( setup )
flock -u 9
$prepare_only && exit 0
ABI=$(cat "$W/abi")
K="$W/kroot-$ABI"

# ---- Initramfs: busybox, the modules, the program and its libraries (per run) ---------------------
RUN=$(mktemp -d "$W/run.XXXXXX")
[ -n "${VMKEEP:-}" ] && echo "run_in_vm: keeping $RUN" >&2 || trap 'rm -rf "$RUN"' EXIT
R="$RUN/root"
mkdir -p "$R"/{bin,proc,sys,dev,tmp,mods,usr/bin,job}
cp /bin/busybox "$R/bin/"
for a in sh mount insmod ip mkdir cat echo poweroff sleep ls uname grep cmp sed head tail cp tar gzip base64; do ln -s busybox "$R/bin/$a"; done
for k in can can-raw can-dev vcan configfs; do
  f=$(find "$K/lib/modules" -name "$k.ko*" | head -1)
  [ -n "$f" ] || continue  # built into this kernel
  case $f in *.xz) xz -dc "$f" ;; *.zst) zstd -dcq "$f" ;; *) cat "$f" ;; esac > "$R/mods/$k.ko"
done
cp "$W/mod-$ABI/irq_sim.ko" "$W/mod-$ABI/gpio-sim.ko" "$R/mods/"
copy_bin() {
  cp "$1" "$R/usr/bin/"
  for l in $(ldd "$1" | grep -oE '/[^ ]+\.so[^ ]*'); do
    mkdir -p "$R$(dirname "$l")"; cp -L "$l" "$R$l"
  done
}
copy_bin "$PROG"
for b in /usr/bin/candump /usr/bin/cansend /usr/bin/gpiodetect /usr/bin/gpioinfo /usr/bin/gpiomon ${VMEXTRA:-}; do
  copy_bin "$b"
done
for f in ${VMFILES:-}; do
  cp "$f" "$R/job/"
done
[ -n "${VMOUT:-}" ] && touch "$R/job/.vmout"
printf '%q ' "$(basename "$PROG")" "$@" > "$R/job/cmd"
cat > "$R/init" <<'INIT'
#!/bin/sh
export PATH=/bin:/usr/bin AMBDROP_REQUIRE_HW=1
mount -t proc p /proc; mount -t sysfs s /sys; mount -t devtmpfs d /dev
for m in can can-raw can-dev vcan configfs irq_sim gpio-sim; do
  [ -f /mods/$m.ko ] || continue
  insmod /mods/$m.ko || echo "guest: insmod $m failed"
done
ip link set lo up
ip link add dev vcan0 type vcan && ip link set vcan0 up
mount -t configfs c /sys/kernel/config; C=/sys/kernel/config/gpio-sim/hil
mkdir $C $C/bank0 $C/bank0/line3; echo 8 > $C/bank0/num_lines; echo hil-sim > $C/bank0/label
echo estop > $C/bank0/line3/name; echo 1 > $C/live
ip link show vcan0 2>/dev/null | grep -q ',UP' && V=up || V=missing
echo "guest: Linux $(uname -r); gpio-sim $(cat $C/dev_name)/$(cat $C/bank0/chip_name) [$(cat $C/bank0/label)]; vcan0 $V"
cd /job; sh -c "$(cat /job/cmd)"; rc=$?
if [ -f /job/.vmout ] && [ -d /job/out ]; then
  echo VM-OUT-BEGIN; tar c -C /job/out . | gzip -1 | base64; echo VM-OUT-END
fi
echo "VM-EXIT=$rc"
poweroff -f
INIT
chmod +x "$R/init"
(cd "$R" && find . | busybox cpio -o -H newc 2>/dev/null | gzip -1) > "$RUN/initrd.gz"

# ---- Boot ----------------------------------------------------------------------------------------
# -nic none: the guest gets no network device at all.
status=0
timeout "${VMTIMEOUT:-300}" qemu-system-x86_64 -accel "${VMACCEL:-tcg}" -m 1024 -smp 1 \
  -nographic -no-reboot -nic none \
  -kernel "$K/boot/vmlinuz-$ABI" -initrd "$RUN/initrd.gz" \
  -append "console=ttyS0 panic=-1 quiet loglevel=3" > "$RUN/console.log" 2>&1 || status=$?
# Drop carriage returns and the firmware's terminal escapes (they glue onto the guest's first line).
tr -d '\r' < "$RUN/console.log" | sed 's/\x1b\[[0-9;?]*[A-Za-z]//g; s/\x1bc//g' > "$RUN/console.txt"
sed '/^VM-OUT-BEGIN$/,/^VM-OUT-END$/d' "$RUN/console.txt" \
  | grep -vE '^\[ *[0-9]+\.[0-9]+\]|^qemu-system|SeaBIOS|iPXE|Booting from|^VM-EXIT=' \
  | sed '/^$/d' || true
rc=$(sed -n 's/^VM-EXIT=\([0-9]*\)$/\1/p' "$RUN/console.txt" | tail -1)
if [ -z "$rc" ]; then
  [ "$status" = 124 ] && echo "run_in_vm: the guest did not finish within ${VMTIMEOUT:-300} s" >&2
  echo "run_in_vm: the guest reported no exit status; its console, last 40 lines:" >&2
  tail -40 "$RUN/console.txt" >&2
  exit 3
fi
# The results asked for did not come out: an output failed, so the run did not succeed.
if [ -n "${VMOUT:-}" ] && grep -q '^VM-OUT-BEGIN$' "$RUN/console.txt"; then
  mkdir -p "$VMOUT"
  if ! grep -q '^VM-OUT-END$' "$RUN/console.txt" ||
    ! sed -n '/^VM-OUT-BEGIN$/,/^VM-OUT-END$/p' "$RUN/console.txt" | sed '1d;$d' \
      | grep -E '^[A-Za-z0-9+/=]+$' | base64 -d | tar xz -C "$VMOUT"; then
    echo "run_in_vm: cannot unpack the guest's out folder into $VMOUT" >&2
    [ "$rc" = 0 ] && rc=3
  fi
fi
exit "$rc"
