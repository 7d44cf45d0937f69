/* ELF32 little-endian ARM executables: PT_LOAD segments at their physical (load)
 * addresses, and the symbol table to name code addresses. */
#ifndef BOARD_TWIN_ELF_H
#define BOARD_TWIN_ELF_H
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  uint32_t paddr, vaddr, filesz, memsz;
  const uint8_t *data; /* filesz bytes */
} elf_segment;

typedef struct {
  uint32_t addr, size;
  int is_func;
  const char *name;
} elf_symbol;

typedef struct {
  uint8_t *raw;
  size_t raw_len;
  uint32_t entry;
  elf_segment *seg;
  size_t nseg;
  elf_symbol *sym; /* sorted by address */
  size_t nsym;
} elf_image;

/* 0 on success, else -1 with the reason in err. */
int elf_load(const char *path, elf_image *img, char *err, size_t err_len);
void elf_free(elf_image *img);
/* Function containing addr, or NULL. */
const elf_symbol *elf_func_at(const elf_image *img, uint32_t addr);
const elf_symbol *elf_find(const elf_image *img, const char *name);

#ifdef __cplusplus
}
#endif

#endif
