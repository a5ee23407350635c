#!/usr/bin/env bash
# Makes sure the Vulkan loader, a Vulkan driver, the Khronos validation layer and Xvfb (for the
# viewer's tests) are present.
# As root on Debian it installs what is missing (Mesa's lavapipe comes from bookworm-backports:
# bookworm's own Mesa 22.3 lacks mesh shaders and ray tracing on the CPU); otherwise it says
# what to install and fails.
set -euo pipefail

need=()
libs=$(ldconfig -p 2>/dev/null || true)
case "$libs" in *libvulkan.so.1*) ;; *) need+=(libvulkan1) ;; esac
ls /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >/dev/null 2>&1 || need+=(vulkan-validationlayers)

# lavapipe must be new enough for task/mesh shaders and ray tracing (Mesa >= 25).
mesa_ok=no
if ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
  v=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || echo 0)
  case "$v" in 2[5-9].*|[3-9][0-9].*) mesa_ok=yes ;; esac
fi
[ "$mesa_ok" = yes ] || need+=(mesa-vulkan-drivers)
# The Python package's tests (scripts/test-python.sh) and the diffusion MRI fit
# (scripts/fetch-dwi.sh) build virtual environments.
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || need+=(python3-venv)
# The viewer's tests open windows on a virtual X server; winit loads the X11 client libraries
# when the window opens, not at link time, so their absence would only show then.
command -v Xvfb >/dev/null 2>&1 || need+=(xvfb)
# ... and close one from outside with xdotool.
command -v xdotool >/dev/null 2>&1 || need+=(xdotool)
window_libs=()
for pair in libX11-xcb.so.1:libx11-xcb1 libXcursor.so.1:libxcursor1 libXrandr.so.2:libxrandr2 \
  libXi.so.6:libxi6 libxkbcommon-x11.so.0:libxkbcommon-x11-0; do
  ldconfig -p 2>/dev/null | grep -q "${pair%%:*}" || window_libs+=("${pair##*:}")
done
need+=("${window_libs[@]}")

# Real scans the tests render when present (DESIGN §8); optional, installed when we can.
optional=()
[ -f /usr/share/doc/libvolpack1-dev/examples/brainsmall.den ] || optional+=(libvolpack1-dev)
[ -f /usr/share/mricron/templates/ch2.nii.gz ] || optional+=(mricron-data)
# The tetrahedralized bunny (scripts/fetch-bunny.sh): tetgen, and npm to fetch the surface.
command -v tetgen >/dev/null 2>&1 || optional+=(tetgen)
command -v npm >/dev/null 2>&1 || optional+=(npm)


can_install=yes
{ [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; } || can_install=no

if [ ${#need[@]} -eq 0 ]; then
  if [ ${#optional[@]} -gt 0 ]; then
    if [ "$can_install" = yes ]; then
      echo "installing test data: ${optional[*]}"
      apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${optional[@]}" >/dev/null \
        || echo "could not install ${optional[*]}: the real-data tests will be skipped" >&2
    else
      echo "note: real-data tests are skipped without: ${optional[*]}" >&2
    fi
  fi
  exit 0
fi

if [ "$can_install" = no ]; then
  echo "missing: ${need[*]}" >&2
  echo "install on Debian 12 (as root): add bookworm-backports, then" >&2
  echo "  apt-get install -t bookworm-backports mesa-vulkan-drivers && apt-get install libvulkan1 vulkan-validationlayers xvfb xdotool ${window_libs[*]}" >&2
  exit 1
fi

echo "installing: ${need[*]}"
src=/etc/apt/sources.list.d/debian.sources
if [ -f "$src" ] && ! grep -rqs 'bookworm-backports' /etc/apt/sources.list.d/ /etc/apt/sources.list; then
  # Derive the backports entry from the machine's own Debian entry, so no mirror is hard-coded.
  awk 'BEGIN{RS="";ORS="\n\n"} NR==1' "$src" | sed 's/^Suites: .*/Suites: bookworm-backports/' \
    > /etc/apt/sources.list.d/backports.sources
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
case " ${need[*]} " in
  *" mesa-vulkan-drivers "*) apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers ;;
esac
apt-get install -y -qq libvulkan1 vulkan-validationlayers
case " ${need[*]} " in
  *" python3-venv "*) apt-get install -y -qq python3-venv ;;
esac
case " ${need[*]} " in
  *" xvfb "*) apt-get install -y -qq xvfb ;;
esac
case " ${need[*]} " in
  *" xdotool "*) apt-get install -y -qq xdotool ;;
esac
[ ${#window_libs[@]} -eq 0 ] || apt-get install -y -qq "${window_libs[@]}"
if [ ${#optional[@]} -gt 0 ]; then
  apt-get install -y -qq "${optional[@]}" >/dev/null || echo "could not install ${optional[*]}: the real-data tests will be skipped" >&2
fi
