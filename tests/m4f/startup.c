/* SPDX-License-Identifier: MIT */
/**
 * @file startup.c
 * @brief Start-up of the core's unit tests on an emulated Cortex-M4F (QEMU's mps2-an386 board):
 *        the vector table, the FPU switched on, .bss zeroed, the semihosting console opened,
 *        then main() and exit() through semihosting. The emulator loads .data in place, so
 *        nothing is copied.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

extern uint32_t __bss_start__;
extern uint32_t __bss_end__;
extern uint32_t __stack_top;
extern int main(void);
extern void __libc_init_array(void);
extern void initialise_monitor_handles(void);

void aenl_m4f_reset(void);
void aenl_m4f_fault(void);
void _init(void);
void _fini(void);

/* Without the C runtime's start files the constructors' hooks are empty here. */
void _init(void)
{
}

void _fini(void)
{
}

/* Initial stack and reset, then the system exceptions (NMI, the faults, SVCall, DebugMonitor,
 * PendSV, SysTick; 0 where the architecture reserves the slot): any of them ends the run with a
 * message, so a crash cannot pass for a test result. No interrupt is enabled. */
__attribute__((section(".vectors"), used)) static void (*const k_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top,
    aenl_m4f_reset,
    aenl_m4f_fault, /* NMI */
    aenl_m4f_fault, /* HardFault */
    aenl_m4f_fault, /* MemManage */
    aenl_m4f_fault, /* BusFault */
    aenl_m4f_fault, /* UsageFault */
    0,
    0,
    0,
    0,
    aenl_m4f_fault, /* SVCall */
    aenl_m4f_fault, /* DebugMonitor */
    0,
    aenl_m4f_fault, /* PendSV */
    aenl_m4f_fault  /* SysTick */
};

void aenl_m4f_reset(void)
{
    /* CP10 and CP11 (the FPU) full access before any floating-point instruction */
    volatile uint32_t *const cpacr = (volatile uint32_t *)0xE000ED88u;
    *cpacr |= 0xFu << 20;
    __asm volatile("dsb\n\tisb" ::: "memory");
    for (uint32_t *p = &__bss_start__; p < &__bss_end__; ++p)
    {
        *p = 0u;
    }
    initialise_monitor_handles();
    __libc_init_array();
    exit(main());
}

void aenl_m4f_fault(void)
{
    (void)puts("\nm4f: FAULT (the test crashed)");
    exit(99);
}
