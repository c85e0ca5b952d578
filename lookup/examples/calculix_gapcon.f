!
!     CalculiX user subroutine gapcon: thermal contact conductance of a
!     rough interface from a tcgen law file, through the lookup C ABI.
!     Replaces ccx's src/gapcon.f (penalty contact, *GAP CONDUCTANCE,
!     USER).
!
!     Build: add lookup_c.f to ccx's sources (before this file), and
!     liblookup.a -lpthread -ldl -lm to the link line of the Makefile.
!     Run with the environment variable TCGEN_LAW=/path/to/law.tclaw.
!
!     Mapping (ccx: d(2) pressure transmitted across the surfaces,
!     temp(1) slave, temp(2) master; tcgen: heat flows from body 1 =
!     slave to body 2 = master, jump = theta_1 - theta_c >= 0):
!       p = d(2),  theta_c = temp(2) (master side, Eq. (2.6)),
!       jump = |temp(1) - temp(2)|
!     lookup_law_eval_at_jump finds the flux |h| with
!     jump(p, |h|, theta_c) = jump, and ak(1) = k = |h| / jump.
!     ccx uses ak(1) only (ak(2..5) not used).
!
!     Units: the law is SI; set t_offset = 273.15d0 for a model in
!     Celsius, and scale d(2) and ak(1) if the model is not in SI.
!
!     The law is opened on the first call; the critical section keeps
!     that safe when ccx runs gapcon from several OpenMP threads.
!
!     Outside the law's table the law file's extrapolation policy
!     decides (tcgen law --extrapolate; the default 'error' stops the
!     analysis with the library's message). When the policy lets the
!     value through (clamp, linear, power), the flags say so and a
!     warning names the element and the query (the first MAX_WARN).
!
      subroutine gapcon(ak,d,flowm,temp,predef,time,ciname,slname,
     &   msname,coords,noel,node,npred,kstep,kinc,area)
      use lookup_c
      implicit none
!
      character*80 ciname,slname,msname
      integer noel,node,npred,kstep,kinc
      real*8 ak(5),d(2),flowm(2),temp(2),predef(2,*),time(*),coords(3),
     &  area
!
      type(c_ptr), save :: law = c_null_ptr
      logical, save :: opened = .false.
      real*8, parameter :: t_offset = 0.d0
!     cap on the conductance where the jump vanishes (full contact)
      real*8, parameter :: k_max = 1.d9
      integer, parameter :: max_warn = 10
      integer, save :: n_warn = 0
      logical :: warn
      character(len=1024) :: path
      integer(c_int32_t) :: status
      integer plen
      type(lookup_flux_value) :: val
!
!$omp critical (tcgen_law_open)
      if (.not. opened) then
        call get_environment_variable('TCGEN_LAW', path, plen)
        if (plen .eq. 0) then
          write(*,*) '*ERROR in gapcon: set TCGEN_LAW to a law file'
          call exit(201)
        endif
        law = lookup_law_open(trim(path)//c_null_char, status)
        if (status .ne. LOOKUP_OK) then
          write(*,*) '*ERROR in gapcon: ', trim(lookup_message())
          call exit(201)
        endif
        status = lookup_law_set_max_conductance(law, k_max)
        opened = .true.
      endif
!$omp end critical (tcgen_law_open)
!
      if (d(2) .le. 0.d0) then
!       no contact pressure: no conduction through the contact
        ak(1) = 0.d0
        return
      endif
      status = lookup_law_eval_at_jump(law, d(2),
     &   abs(temp(1) - temp(2)), temp(2) + t_offset, val)
      if (status .ne. LOOKUP_OK) then
        write(*,*) '*ERROR in gapcon: element', noel, ': ',
     &     trim(lookup_message())
        call exit(201)
      endif
      ak(1) = val%conductance
!
      if (iand(val%flags, LOOKUP_FLAG_EXTRAPOLATED) .ne. 0) then
!$omp critical (tcgen_law_warn)
        n_warn = n_warn + 1
        warn = n_warn .le. max_warn
!$omp end critical (tcgen_law_warn)
        if (warn) then
          write(*,'(a,i0,a,es12.5,a,es12.5,a,es12.5,2a,i0,a)')
     &      ' *WARNING in gapcon: element ', noel, ': p = ', d(2),
     &      ' Pa, jump = ', abs(temp(1) - temp(2)), ' K, theta_c = ',
     &      temp(2) + t_offset, ' K outside the law table ',
     &      '(extrapolated, flags ', val%flags, ')'
          if (n_warn .eq. max_warn) write(*,*)
     &      '*WARNING in gapcon: further extrapolation warnings ',
     &      'suppressed'
        endif
      endif
!
      return
      end
