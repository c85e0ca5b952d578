!     Abaqus/Standard user subroutines: thermal contact conductance of a
!     rough interface from a tcgen law file, through the lookup C ABI.
!
!     Build: compile lookup_c.f with this file (or concatenate them) and
!     link liblookup.a, e.g. in abaqus_v6.env:
!       link_sl += ['/path/to/liblookup.a', '-lpthread', '-ldl', '-lm']
!     Run with the environment variable TCGEN_LAW=/path/to/law.tclaw and
!       *GAP CONDUCTANCE, USER
!     in the surface interaction.
!
!     Mapping (Abaqus: q = AK(1) (TEMP(1) - TEMP(2)), point A on the
!     slave, B on the master; tcgen: heat from body 1 = slave to
!     body 2 = master, jump = theta_1 - theta_c >= 0, Eq. (2.6)):
!       contact pressure  p       = D(2)
!       contact temp.     theta_c = TEMP(2)  (master side, Eq. (2.6))
!       jump                      = |TEMP(1) - TEMP(2)|
!     The law gives the jump as a function of the flux |h|, so GAPCON
!     inverts it (lookup_law_eval_at_jump): the |h| with
!     jump(p, |h|, theta_c) = TEMP(1) - TEMP(2), and k = |h| / jump.
!       AK(1) = k,  AK(2) = dk/d(clearance) = 0,  AK(3) = dk/dp
!     (AK(2), AK(3) matter in fully coupled temperature-displacement
!     analyses only). Reversed heat flow uses |jump| (the law of the
!     opposite direction is not tabulated).
!
!     Units: the law is SI. Set T_OFFSET = 273.15 for a model in
!     Celsius; scale D(2) and AK if the model is not in SI units.
!
!     Outside the law's table the law file's extrapolation policy
!     decides (tcgen law --extrapolate; the default 'error' stops the
!     analysis with the library's message in the .msg file). When the
!     policy lets the value through (clamp, linear, power), the flags
!     say so and GAPCON issues an Abaqus warning (the first MAX_WARN).
!
!     The law is opened once, in UEXTERNALDB at the start of the
!     analysis (before the solver threads run GAPCON), and freed at the
!     end; the handle is read-only afterwards, so GAPCON is thread safe.
!
      module tcgen_law_state
      use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr
      implicit none
      type(c_ptr), save :: law = c_null_ptr
!     Model temperature + T_OFFSET = kelvin.
      double precision, parameter :: T_OFFSET = 0.0d0
!     Cap on the conductance where the jump vanishes (full contact).
      double precision, parameter :: K_MAX = 1.0d9
!     Extrapolation warnings issued (at most MAX_WARN).
      integer, parameter :: MAX_WARN = 10
      integer, save :: n_warn = 0
      end module tcgen_law_state
!
      SUBROUTINE UEXTERNALDB(LOP,LRESTART,TIME,DTIME,KSTEP,KINC)
      use lookup_c
      use tcgen_law_state
      INCLUDE 'ABA_PARAM.INC'
      DIMENSION TIME(2)
      character(len=1024) :: path
      integer(c_int32_t) :: status
      integer :: plen
!
      IF (LOP .EQ. 0 .OR. (LOP .EQ. 4 .AND. .NOT. c_associated(law)))
     &  THEN
!       Start of the analysis (or of a restart): open the law.
        call get_environment_variable('TCGEN_LAW', path, plen)
        if (plen .eq. 0) then
          CALL STDB_ABQERR(-3, 'GAPCON: set TCGEN_LAW to a law file',
     &      0, 0.0d0, ' ')
        end if
        law = lookup_law_open(trim(path)//c_null_char, status)
        if (status .ne. LOOKUP_OK) then
          WRITE(7,*) 'GAPCON: ', trim(lookup_message())
          CALL STDB_ABQERR(-3, 'GAPCON: cannot open TCGEN_LAW (.msg)',
     &      0, 0.0d0, ' ')
        end if
        status = lookup_law_set_max_conductance(law, K_MAX)
      ELSE IF (LOP .EQ. 3) THEN
!       End of the analysis.
        call lookup_law_free(law)
        law = c_null_ptr
      END IF
      RETURN
      END
!
      SUBROUTINE GAPCON(AK,D,FLOWM,TEMP,PREDEF,TIME,CINAME,SLNAME,
     1 MSNAME,COORDS,NOEL,NODE,NPRED,KSTEP,KINC)
      use lookup_c
      use tcgen_law_state
      INCLUDE 'ABA_PARAM.INC'
      CHARACTER*80 CINAME,SLNAME,MSNAME
      DIMENSION AK(5),D(2),FLOWM(2),TEMP(2),PREDEF(2,*),TIME(2),
     1 COORDS(3)
      type(lookup_flux_value) :: val
      integer(c_int32_t) :: status
      real(c_double) :: p, jump, theta
      logical :: warn
!
      AK(2) = 0.0d0
      p = D(2)
      IF (p .LE. 0.0d0) THEN
!       No contact pressure: no conduction through the contact.
        AK(1) = 0.0d0
        AK(3) = 0.0d0
        RETURN
      END IF
      theta = TEMP(2) + T_OFFSET
      jump = abs(TEMP(1) - TEMP(2))
      status = lookup_law_eval_at_jump(law, p, jump, theta, val)
      IF (status .NE. LOOKUP_OK) THEN
!       Unit 7 is the .msg file.
        WRITE(7,*) 'GAPCON: element', NOEL, ' node', NODE, ': ',
     &    trim(lookup_message())
        CALL STDB_ABQERR(-3, 'GAPCON: contact law failed (.msg)',
     &    0, 0.0d0, ' ')
      END IF
      AK(1) = val%conductance
      AK(3) = val%d_conductance_dp
      IF (iand(val%flags, LOOKUP_FLAG_EXTRAPOLATED) .NE. 0) THEN
!$omp critical (tcgen_law_warn)
        n_warn = n_warn + 1
        warn = n_warn .LE. MAX_WARN
!$omp end critical (tcgen_law_warn)
        IF (warn) THEN
          WRITE(7,*) 'GAPCON: element', NOEL, ' node', NODE,
     &      ': p, jump, theta_c =', p, jump, theta,
     &      ' outside the law table (extrapolated, flags', val%flags,
     &      ')'
          CALL STDB_ABQERR(-1, 'GAPCON: contact law extrapolated '//
     &      '(%I warning(s); see .msg)', n_warn, 0.0d0, ' ')
        END IF
      END IF
      RETURN
      END
