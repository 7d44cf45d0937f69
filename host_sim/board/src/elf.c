/* ELF32 loader for the flashable image: program headers (PT_LOAD at p_paddr, so .data's
 * initial values land in flash as on the chip) and .symtab for naming addresses. */
#include "board_twin/elf.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t rd32(const uint8_t *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static uint16_t rd16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }

static int cmp_sym(const void *a, const void *b) {
  const elf_symbol *x = a, *y = b;
  return x->addr < y->addr ? -1 : x->addr > y->addr;
}

int elf_load(const char *path, elf_image *img, char *err, size_t n) {
  memset(img, 0, sizeof *img);
  FILE *f = fopen(path, "rb");
  if (!f) { snprintf(err, n, "%s: cannot open", path); return -1; }
  fseek(f, 0, SEEK_END);
  long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  img->raw = malloc(len > 0 ? (size_t)len : 1);
  img->raw_len = len > 0 ? (size_t)len : 0;
  if (fread(img->raw, 1, img->raw_len, f) != img->raw_len) { fclose(f); snprintf(err, n, "%s: read error", path); goto fail; }
  fclose(f);
  const uint8_t *r = img->raw;
  if (img->raw_len < 52 || memcmp(r, "\x7f" "ELF", 4) != 0 || r[4] != 1 || r[5] != 1) {
    snprintf(err, n, "%s: not a little-endian ELF32 file", path); goto fail;
  }
  if (rd16(r + 18) != 40) { snprintf(err, n, "%s: not an ARM ELF (e_machine %u)", path, rd16(r + 18)); goto fail; }
  img->entry = rd32(r + 24);
  uint32_t phoff = rd32(r + 28), shoff = rd32(r + 32);
  uint16_t phentsize = rd16(r + 42), phnum = rd16(r + 44), shentsize = rd16(r + 46), shnum = rd16(r + 48);
  if ((uint64_t)phoff + (uint64_t)phnum * phentsize > img->raw_len ||
      (uint64_t)shoff + (uint64_t)shnum * shentsize > img->raw_len) {
    snprintf(err, n, "%s: truncated headers", path); goto fail;
  }
  img->seg = calloc(phnum ? phnum : 1, sizeof *img->seg);
  for (uint16_t i = 0; i < phnum; i++) {
    const uint8_t *ph = r + phoff + (size_t)i * phentsize;
    if (rd32(ph) != 1 /* PT_LOAD */) continue;
    elf_segment *s = &img->seg[img->nseg];
    uint32_t off = rd32(ph + 4);
    s->vaddr = rd32(ph + 8); s->paddr = rd32(ph + 12);
    s->filesz = rd32(ph + 16); s->memsz = rd32(ph + 20);
    if ((uint64_t)off + s->filesz > img->raw_len) { snprintf(err, n, "%s: segment %u outside the file", path, i); goto fail; }
    s->data = r + off;
    img->nseg++;
  }
  /* .symtab and its string table */
  for (uint16_t i = 0; i < shnum; i++) {
    const uint8_t *sh = r + shoff + (size_t)i * shentsize;
    if (rd32(sh + 4) != 2 /* SHT_SYMTAB */) continue;
    uint32_t off = rd32(sh + 16), size = rd32(sh + 20), link = rd32(sh + 24), entsize = rd32(sh + 36);
    if (link >= shnum || entsize < 16 || (uint64_t)off + size > img->raw_len) continue;
    const uint8_t *strh = r + shoff + (size_t)link * shentsize;
    uint32_t stroff = rd32(strh + 16), strsize = rd32(strh + 20);
    if ((uint64_t)stroff + strsize > img->raw_len) continue;
    size_t count = size / entsize;
    img->sym = calloc(count ? count : 1, sizeof *img->sym);
    for (size_t k = 0; k < count; k++) {
      const uint8_t *st = r + off + k * entsize;
      uint32_t name = rd32(st), value = rd32(st + 4), ssize = rd32(st + 8);
      uint8_t type = st[12] & 0xf;
      /* objects, functions, and linker-script symbols (NOTYPE, e.g. _estack); not $t/$d mapping symbols */
      if (type > 2 || name >= strsize || rd16(st + 14) == 0) continue;
      if (r[stroff + name] == '$' || r[stroff + name] == 0) continue;
      elf_symbol *e = &img->sym[img->nsym++];
      e->is_func = type == 2;
      e->addr = e->is_func ? value & ~1u : value; /* Thumb bit */
      e->size = ssize;
      e->name = (const char *)r + stroff + name;
    }
    qsort(img->sym, img->nsym, sizeof *img->sym, cmp_sym);
    break;
  }
  return 0;
fail:
  elf_free(img);
  return -1;
}

void elf_free(elf_image *img) {
  free(img->raw);
  free(img->seg);
  free(img->sym);
  memset(img, 0, sizeof *img);
}

const elf_symbol *elf_func_at(const elf_image *img, uint32_t addr) {
  const elf_symbol *best = NULL;
  for (size_t i = 0; i < img->nsym && img->sym[i].addr <= addr; i++) {
    const elf_symbol *s = &img->sym[i];
    if (s->is_func && addr < s->addr + (s->size ? s->size : 2)) best = s;
  }
  return best;
}

const elf_symbol *elf_find(const elf_image *img, const char *name) {
  for (size_t i = 0; i < img->nsym; i++)
    if (strcmp(img->sym[i].name, name) == 0) return &img->sym[i];
  return NULL;
}
