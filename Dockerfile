# softplc in a container: a build stage, then a slim runtime with the binary
# and the examples. See docs/docker.md.
#
#   docker build -t softplc .
#   docker run --rm -p 8080:8080 -p 5010:5010 -p 5020:5020 softplc \
#       serve /usr/share/softplc/examples/blink.il --http 0.0.0.0:8080 \
#       --mc 0.0.0.0:5010 --modbus 0.0.0.0:5020

FROM rust:1.95-slim-bookworm AS build
WORKDIR /src
COPY . .
# The lock file pins every dependency; the OPC UA server is in by default.
RUN cargo build --release --locked -p softplc \
    && strip target/release/softplc \
    && strip --strip-unneeded target/release/deps/libsoftplc_fmu.so

FROM debian:bookworm-slim
RUN useradd --system --uid 10001 --create-home --home-dir /var/lib/softplc softplc
COPY --from=build /src/target/release/softplc /usr/local/bin/softplc
# The binary `softplc fmu` puts in an FMU, found next to softplc.
COPY --from=build /src/target/release/deps/libsoftplc_fmu.so /usr/local/bin/libsoftplc_fmu.so
COPY examples /usr/share/softplc/examples
USER softplc
# Latched devices and the OPC UA certificate store live here: mount a volume
# to keep them across containers.
WORKDIR /var/lib/softplc
ENV HOME=/var/lib/softplc
VOLUME ["/var/lib/softplc"]
# MC protocol, Modbus TCP, web monitor, OPC UA (as the documented commands use them).
EXPOSE 5010 5020 8080 4840
ENTRYPOINT ["softplc"]
CMD ["serve", "/usr/share/softplc/examples/blink.il", "--http", "0.0.0.0:8080"]
