# trav on Debian bookworm, from a clone of this repository:
#   docker build -t trav .
#   docker run --rm -v "$PWD/out:/trav/out" trav                  # scripts/demo: out/demo/video.mp4, run.mcap
#   docker run --rm trav build/scenarios/trav run --no-video       # any trav command
#   docker run --rm trav scripts/test                              # the tests (installs their packages)
# Everything comes from Debian's packages through scripts/install-deps, as on a bare machine; the
# Slurm packages are left out (only `--slurm` runs need them).
FROM debian:bookworm
ENV DEBIAN_FRONTEND=noninteractive TRAV_INSTALL_CLUSTER=0
WORKDIR /trav
# the packages first, in their own layer: a change to the sources does not reinstall them
COPY scripts/install-deps scripts/install-deps
RUN scripts/install-deps && rm -rf /var/lib/apt/lists/*
COPY . .
RUN scripts/build
CMD ["scripts/demo"]
