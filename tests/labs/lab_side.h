/* tests/labs/lab_side.h: for the lab wrappers (lab_*_side.c). */
#ifndef LAB_SIDE_H
#define LAB_SIDE_H
/* The two builds of the lab's code in one program: LAB_SIDE is ref (examples/pbrtv3) or stu (the
 * student's file). lab_NN_side.c is compiled once per side; LAB_FN(name) is its exported name. */
#define LAB_CAT2(a, b) a##_##b
#define LAB_CAT(a, b) LAB_CAT2(a, b)
#define LAB_FN(name) LAB_CAT(LAB_SIDE, name)
#endif
