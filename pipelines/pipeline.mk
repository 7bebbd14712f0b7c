# Make-style staged runs, shared by every bundled scene (include it from pipelines/<scene>/Makefile).
#   make -C pipelines/<scene>                 import, grid, expand, refine, compact, index, certify
#                                             what is out of date
#   make -C pipelines/<scene> eval            the accuracy experiment on the playback file
#   make -C pipelines/<scene> expand THREADS=2 MAX_SECONDS=600
#   make -C pipelines/<scene> inspect         summary of the state directory
# Each stage records the hashes of what it consumed and does nothing when they are unchanged
# ("unchanged" / "nothing to do"), so the targets are phony and always safe to re-run.
BUILD ?= $(abspath $(dir $(lastword $(MAKEFILE_LIST)))/../build)
SCENE ?= scene.toml
STATE ?= state
THREADS ?= 1
MAX_SECONDS ?=
STAGES := $(BUILD)/stages

.PHONY: all import grid expand refine compact index certify eval inspect clean
NODES ?= all
all: certify

import:
	$(STAGES)/hapstate-import $(SCENE) --state $(STATE)
grid: import
	$(STAGES)/hapstate-grid --state $(STATE)
expand: grid
	$(STAGES)/hapstate-expand --state $(STATE) --threads $(THREADS) $(if $(MAX_SECONDS),--max-seconds $(MAX_SECONDS))
refine: expand
	$(STAGES)/hapstate-refine --state $(STATE) --threads $(THREADS)
compact: refine
	$(STAGES)/hapstate-compact --state $(STATE)
index: compact
	$(STAGES)/hapstate-index --state $(STATE) --nodes $(NODES)
certify: index
	$(STAGES)/hapstate-certify --state $(STATE) --threads $(THREADS)
eval: index
	$(BUILD)/tools/hapstate-eval --state $(STATE)
inspect:
	$(BUILD)/tools/hapstate-inspect --state $(STATE) summary
clean:
	rm -rf $(STATE)
