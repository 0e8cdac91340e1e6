/* lvcl: renders a glTF scene on an OpenCL device. */
#include "app.h"

int main(int argc, char **argv)
{
    return lvcl_app_main(argc, argv, NULL);
}
