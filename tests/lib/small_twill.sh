# Sourced by the material tests that need a real addressed draft, small:
# write_small_twill ROOT OUT writes the cloth spec of wi_32twill (a real WIF,
# 62 x 62 threads) at one cell a thread and 4 layers, which bakes in seconds
# per crossing and is refused as a whole repeat at the default texels.
write_small_twill() {
  printf '{"weave": {"wif": "%s"}, "resolution": {"cells_per_thread": 1, "layers": 4}}\n' \
    "$1/testscenes/wif/real/wi_32twill.wif" >"$2"
}
